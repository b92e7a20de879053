// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DataPaths.h
/// @brief Where the programs find the project's data (Data/: the default face, rigs,
/// scripts), the ICT-FaceKit data (MORPHNODE_FACEKIT_DIR) and the MakeHuman avatar
/// (MORPHNODE_AVATAR_DIR), as configured by CMake.

#include <string>

namespace morphnode
{
namespace appkit
{
/// The project's Data folder, e.g. DataPath("DefaultFace/default_head.glb").
std::string DataPath(const std::string& relative);
/// A file of the ICT-FaceKit data folder (it may be absent: callers check).
std::string FaceKitPath(const std::string& relative);
/// A file of the MakeHuman avatar data folder (MORPHNODE_AVATAR_DIR; it may be absent).
std::string AvatarPath(const std::string& relative);
/// Data/DefaultFace/default_head.glb (the project's head: skin, mouth, teeth, tongue, eyes, ...).
std::string DefaultFace();
} // namespace appkit
} // namespace morphnode
