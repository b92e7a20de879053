// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphPartData (the part convention in field data): the names as docs/materials.md and
// the readers' users know them, a round trip of every field, the checks on numeric arrays
// (wrong count, not finite, a material index that is not one), the frame's defaults kept
// where absent, and the fields of a glTF part (node name fallback, unit axes, scale).
#include "vtkMorphPartData.h"

#include "base/Error.h"
#include "gltf/GltfScene.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace partdata = vtkMorphPartData;

TEST(MorphPartData, NamesAreTheConvention)
{
  EXPECT_STREQ(partdata::PartNameArray, "PartName");
  EXPECT_STREQ(partdata::NodeNameArray, "NodeName");
  EXPECT_STREQ(partdata::MaterialNameArray, "MaterialName");
  EXPECT_STREQ(partdata::BaseColorArray, "BaseColor");
  EXPECT_STREQ(partdata::NodeOriginArray, "NodeOrigin");
  EXPECT_STREQ(partdata::NodeAxesArray, "NodeAxes");
  EXPECT_STREQ(partdata::MaterialIndexArray, "MaterialIndex");
  EXPECT_STREQ(partdata::MaterialSourceArray, "MaterialSource");
}

TEST(MorphPartData, RoundTrip)
{
  partdata::PartFields in;
  in.PartName = "Jaw/Lips";
  in.NodeName = "Jaw";
  in.MaterialName = "Lips";
  in.BaseColor = std::array<double, 4>{ { 0.7, 0.3, 0.3, 1 } };
  in.NodeOrigin = std::array<double, 3>{ { 1, 2, 3 } };
  in.NodeAxes = std::array<double, 9>{ { 0, 1, 0, -1, 0, 0, 0, 0, 1 } };
  in.MaterialIndex = 2;
  in.MaterialSource = "head.glb";
  vtkNew<vtkFieldData> fd;
  partdata::SetPartFields(fd, in);
  const partdata::PartFields out = partdata::GetPartFields(fd);
  EXPECT_EQ(out.PartName, in.PartName);
  EXPECT_EQ(out.NodeName, in.NodeName);
  EXPECT_EQ(out.MaterialName, in.MaterialName);
  EXPECT_EQ(out.BaseColor, in.BaseColor);
  EXPECT_EQ(out.NodeOrigin, in.NodeOrigin);
  EXPECT_EQ(out.NodeAxes, in.NodeAxes);
  EXPECT_EQ(out.MaterialIndex, 2);
  EXPECT_EQ(out.MaterialSource, "head.glb");
  // Written as plain arrays any VTK user reads.
  auto* name = vtkStringArray::SafeDownCast(fd->GetAbstractArray("PartName"));
  ASSERT_NE(name, nullptr);
  EXPECT_EQ(name->GetValue(0), "Jaw/Lips");
  EXPECT_EQ(fd->GetArray("BaseColor")->GetNumberOfValues(), 4);

  // Absent fields stay absent; names fall back.
  vtkNew<vtkFieldData> empty;
  const partdata::PartFields none = partdata::GetPartFields(empty);
  EXPECT_TRUE(none.PartName.empty());
  EXPECT_FALSE(none.BaseColor || none.NodeOrigin || none.NodeAxes);
  EXPECT_EQ(none.MaterialIndex, -1);
  EXPECT_EQ(partdata::GetPartName(empty, "block"), "block");
  EXPECT_EQ(partdata::GetNodeName(nullptr, "node"), "node");
  std::array<double, 3> origin{ { 5, 5, 5 } };
  std::array<double, 9> axes{};
  EXPECT_FALSE(partdata::GetNodeFrame(empty, origin, axes));
  EXPECT_EQ(origin[0], 5) << "left as it was";
}

TEST(MorphPartData, NumbersChecked)
{
  vtkNew<vtkFieldData> fd;
  const double three[3] = { 1, 0, 0 };
  partdata::SetNumbers(fd, partdata::NodeAxesArray, three, 3);
  std::array<double, 3> origin{};
  std::array<double, 9> axes{};
  try
  {
    partdata::GetNodeFrame(fd, origin, axes);
    ADD_FAILURE() << "NodeAxes of 3 values accepted";
  }
  catch (const morphnode::InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("NodeAxes has 3 values, not 9"), std::string::npos)
      << e.what();
  }
  const double nan[3] = { std::nan(""), 0, 0 };
  partdata::SetNumbers(fd, partdata::NodeOriginArray, nan, 3);
  fd->RemoveArray(partdata::NodeAxesArray);
  EXPECT_THROW(partdata::GetNodeFrame(fd, origin, axes), morphnode::InputError);
  const double half = 0.5;
  vtkNew<vtkFieldData> material;
  partdata::SetNumbers(material, partdata::MaterialIndexArray, &half, 1);
  EXPECT_THROW(partdata::GetPartFields(material), morphnode::InputError);
  // GetNumbers without a count reads what is there, of any layout.
  vtkNew<vtkDoubleArray> tuples;
  tuples->SetName("Pairs");
  tuples->SetNumberOfComponents(2);
  tuples->InsertNextTuple2(1, 2);
  tuples->InsertNextTuple2(3, 4);
  fd->AddArray(tuples);
  EXPECT_EQ(partdata::GetNumbers(fd, "Pairs"), (std::vector<double>{ 1, 2, 3, 4 }));
  EXPECT_TRUE(partdata::GetNumbers(fd, "Absent").empty());
}

TEST(MorphPartData, FromGltfPart)
{
  morphnode::GltfScene scene;
  scene.Nodes.resize(2);
  scene.Nodes[1].Name = "";
  morphnode::GltfPart part;
  part.Name = "node1";
  part.Node = 1;
  part.MaterialName = "Skin";
  part.BaseColor = { { 0.5, 0.5, 0.5, 1 } };
  part.World = morphnode::GltfComposeTrs(
    { { 1, 2, 3 } }, { { 0, 0, std::sqrt(0.5), std::sqrt(0.5) } }, { { 2, 2, 2 } });
  const partdata::PartFields local = partdata::FromGltfPart(scene, part, false, 1.0);
  EXPECT_EQ(local.NodeName, "node1") << "a nameless node is node<n>";
  EXPECT_FALSE(local.NodeOrigin || local.NodeAxes) << "no world frame in the node's frame";
  const partdata::PartFields world = partdata::FromGltfPart(scene, part, true, 10.0);
  ASSERT_TRUE(world.NodeOrigin && world.NodeAxes);
  EXPECT_EQ(*world.NodeOrigin, (std::array<double, 3>{ { 10, 20, 30 } }));
  // A quarter turn about z, scaled by 2: unit axes x -> y, y -> -x.
  const std::array<double, 9> expected{ { 0, 1, 0, -1, 0, 0, 0, 0, 1 } };
  for (int i = 0; i < 9; ++i)
  {
    EXPECT_NEAR((*world.NodeAxes)[i], expected[i], 1e-12) << i;
  }
}
