// SPDX-License-Identifier: BSD-3-Clause
// tinygltf's implementation, compiled here from Debian's header (see TinyGltfConfig.h).
#define TINYGLTF_IMPLEMENTATION
#include "TinyGltfConfig.h"
