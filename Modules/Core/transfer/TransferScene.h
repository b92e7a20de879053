// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file TransferScene.h
/// @brief The transfer between glTF scenes (gltf/GltfScene.h): a source face's parts with
/// targets merged into one TransferSource, and a target scene given the source's targets
/// on its own points (its own targets, if any, replaced). What the MorphTransfer program,
/// MorphAvatar's --targets-from and vtkMorphTransferFilter's callers share.

#include "gltf/GltfScene.h"
#include "transfer/Transfer.h"

namespace morphnode
{
/// Every part of `scene` that has targets, merged (points, triangles) into one source; the
/// target names are the union in order of first appearance (a part without a name moves
/// nothing under it). Throws InputError when no part has targets.
TransferSource MakeTransferSource(const GltfScene& scene);

/// Every part of `target` merged into one surface (world space as loaded), and where each
/// part's points start in it.
TransferSurface MergeParts(const GltfScene& target, std::vector<size_t>& partOffsets);

/// Transfers `source`'s targets onto every part of `target` (merged, so that a head of
/// several parts fits as one): each part's Targets become the source's, by name, its
/// default weights zero. Returns the transfer's result (deltas over the merged points).
TransferResult TransferOntoScene(
  const TransferSource& source, GltfScene& target, const TransferOptions& options = {});
} // namespace morphnode
