// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file TinyGltfConfig.h
/// @brief Internal to the gltf concept: tinygltf as this library builds it (one
/// configuration for every file that includes it). No image decoding (no stb_image: images
/// are skipped by a no-op loader), no external image files, and no default file system
/// (GltfScene.cpp gives callbacks that only open files in the input's folder).

#include <fstream> // tinygltf 2.7 uses it for writing even with TINYGLTF_NO_FS

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_FS
#include <tiny_gltf.h>
