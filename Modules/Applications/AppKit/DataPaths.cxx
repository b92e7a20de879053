// SPDX-License-Identifier: BSD-3-Clause
#include "DataPaths.h"

namespace morphnode
{
namespace appkit
{
std::string DataPath(const std::string& relative)
{
  return std::string(MORPHNODE_DATA_DIR) + "/" + relative;
}

std::string FaceKitPath(const std::string& relative)
{
  return std::string(MORPHNODE_FACEKIT_DIR) + "/" + relative;
}

std::string AvatarPath(const std::string& relative)
{
  return std::string(MORPHNODE_AVATAR_DIR) + "/" + relative;
}

std::string DefaultFace()
{
  return DataPath("DefaultFace/default_head.glb");
}
} // namespace appkit
} // namespace morphnode
