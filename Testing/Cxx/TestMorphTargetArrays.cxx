// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphTargetArrays, the module's one owner of the target<k>_* / TargetNames convention:
// it reads what vtkGLTFReader builds, agrees with vtkMorphTargetReader, round-trips a
// MorphMesh through VTK exactly (float and double) and converts arrays of any type.
#include "vtkMorphTargetArrays.h"
#include "vtkMorphTargetReader.h"

#include "base/Error.h"

#include "MorphNodeTestErrors.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArrayRange.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkGLTFReader.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSOADataArrayTemplate.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <variant>
#include <vector>

namespace arrays = vtkMorphTargetArrays;
using arrays::Kind;
using morphnode::AttributeRole;
using morphnode::InputError;
using morphnode::MorphAttribute;
using morphnode::MorphMesh;

using morphnode_test::ErrorOf;

namespace
{
const std::string DefaultFace =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";
const std::string IctFace = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";

/// The first poly data of vtkGLTFReader's output, targets as arrays (not applied).
vtkSmartPointer<vtkPolyData> ReadWithVtkGLTFReader(const std::string& path)
{
  vtkNew<vtkGLTFReader> reader;
  reader->SetFileName(path.c_str());
  reader->SetApplyDeformationsToGeometry(false);
  reader->Update();
  const auto polys = vtkCompositeDataSet::GetDataSets<vtkPolyData>(reader->GetOutput());
  return polys.empty() ? nullptr : polys.front();
}

template <typename T>
std::vector<T> Dense(const MorphAttribute<T>& attribute, size_t target)
{
  std::vector<T> values(attribute.GetNumberOfPoints() * attribute.GetNumberOfComponents());
  attribute.GetTarget(target).ToDense(values.data());
  return values;
}

/// The values of a VTK array as doubles, through VTK's own range (what the test compares
/// the helper's conversion against).
std::vector<double> Values(vtkDataArray* array)
{
  const auto range = vtk::DataArrayValueRange(array);
  return std::vector<double>(range.begin(), range.end());
}

/// Checks the helper's mesh against the arrays vtkGLTFReader built: every target<k>_position
/// (and _normal) array is target k + 1 of the mesh, value for value.
void ExpectMeshHoldsTheArrays(vtkPolyData* poly, const MorphMesh& mesh, bool normals)
{
  const size_t numTargets = mesh.GetNumberOfTargets() - 1;
  const auto& positions = std::get<MorphAttribute<float>>(mesh.GetAttribute(0));
  EXPECT_EQ(std::vector<double>(positions.GetNeutral().begin(), positions.GetNeutral().end()),
    Values(poly->GetPoints()->GetData()));
  for (size_t k = 0; k < numTargets; ++k)
  {
    vtkDataArray* array =
      poly->GetPointData()->GetArray(("target" + std::to_string(k) + "_position").c_str());
    ASSERT_NE(array, nullptr) << k;
    const std::vector<float> deltas = Dense(positions, k + 1);
    ASSERT_EQ(std::vector<double>(deltas.begin(), deltas.end()), Values(array)) << "target " << k;
  }
  ASSERT_EQ(mesh.GetNumberOfAttributes(), normals ? 2u : 1u);
  if (normals)
  {
    const auto& n = std::get<MorphAttribute<float>>(mesh.GetAttribute(1));
    EXPECT_EQ(n.GetRole(), AttributeRole::Normal);
    for (size_t k = 0; k < numTargets; ++k)
    {
      vtkDataArray* array =
        poly->GetPointData()->GetArray(("target" + std::to_string(k) + "_normal").c_str());
      ASSERT_NE(array, nullptr) << k;
      const std::vector<float> deltas = Dense(n, k + 1);
      ASSERT_EQ(std::vector<double>(deltas.begin(), deltas.end()), Values(array)) << "target " << k;
    }
  }
}

/// A small mesh of T with a Position and a Normal attribute, 3 targets (one sparse, one
/// dense, one that moves nothing), 2 triangles.
template <typename T>
MorphMesh MakeMesh()
{
  const size_t np = 4;
  MorphMesh mesh(np);
  mesh.SetTargetNames({ "Neutral", "jawOpen", "smile", "nothing" });
  const std::vector<T> neutral = { 0, 0, 0, 1, 0, 0, 1, 1, T(0.1), 0, 1, T(1) / T(3) };
  const std::vector<std::vector<T>> deltas = {
    { 0, 0, 0, 0, 0, 0, 0, T(-0.25), 0, 0, T(1e-7), 0 },
    { T(0.1), T(0.2), T(0.3), T(-0.4), T(0.5), T(0.6), T(0.7), T(0.8), T(0.9), T(1), T(1.1),
      T(1.2) },
    std::vector<T>(3 * np, T(0)),
  };
  {
    auto& positions = mesh.AddAttribute<T>("Points", AttributeRole::Position, 3);
    positions.SetNeutral(neutral.data());
    for (const auto& d : deltas)
    {
      positions.AddRelativeTarget(d.data(), 0.5);
    }
  }
  {
    auto& normals = mesh.AddAttribute<T>("Normals", AttributeRole::Normal, 3);
    const std::vector<T> up = { 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 };
    normals.SetNeutral(up.data());
    for (const auto& d : deltas)
    {
      std::vector<T> dn(d.rbegin(), d.rend());
      normals.AddRelativeTarget(dn.data(), 0.5);
    }
  }
  mesh.SetTriangles({ 0, 1, 2, 0, 2, 3 });
  return mesh;
}

template <typename T>
void ExpectRoundTrip()
{
  const MorphMesh mesh = MakeMesh<T>();
  const vtkSmartPointer<vtkPolyData> poly = arrays::ToPolyData(mesh);
  const int type = std::is_same_v<T, float> ? VTK_FLOAT : VTK_DOUBLE;
  EXPECT_EQ(poly->GetPoints()->GetDataType(), type);
  ASSERT_NE(poly->GetPointData()->GetArray("target2_position"), nullptr);
  EXPECT_EQ(poly->GetPointData()->GetArray("target2_position")->GetDataType(), type);
  EXPECT_NE(poly->GetPointData()->GetArray("target2_normal"), nullptr);
  EXPECT_EQ(poly->GetPointData()->GetNormals()->GetDataType(), type);
  EXPECT_EQ(poly->GetPointData()->GetArray("target3_position"), nullptr);

  arrays::ReadOptions options;
  options.Triangles = true;
  const arrays::MeshFromVTK back = arrays::ToMorphMesh(poly, options);
  const MorphMesh& m = back.Mesh;
  EXPECT_EQ(m.GetTargetNames(), mesh.GetTargetNames());
  EXPECT_EQ(m.GetTriangles(), mesh.GetTriangles());
  EXPECT_EQ(back.Normals, poly->GetPointData()->GetNormals());
  EXPECT_EQ(back.TargetArrays.size(), 6u);
  ASSERT_EQ(m.GetNumberOfAttributes(), 2u);
  for (size_t a = 0; a < 2; ++a)
  {
    const auto& in = std::get<MorphAttribute<T>>(mesh.GetAttribute(a));
    const auto* out = std::get_if<MorphAttribute<T>>(&m.GetAttribute(a));
    ASSERT_NE(out, nullptr) << "attribute " << a << " changed type";
    EXPECT_EQ(out->GetName(), in.GetName());
    EXPECT_EQ(out->GetRole(), in.GetRole());
    EXPECT_EQ(out->GetNeutral(), in.GetNeutral());
    ASSERT_EQ(out->GetNumberOfTargets(), in.GetNumberOfTargets());
    for (size_t t = 1; t < in.GetNumberOfTargets(); ++t)
    {
      EXPECT_EQ(Dense(*out, t), Dense(in, t)) << "attribute " << a << " target " << t;
    }
  }
}

} // namespace

// A head's targets are the union over its parts in order of first appearance (the morph
// filter's naming), not the first part's: a part may lack targets another has.
TEST(MorphTargetArrays, FaceTargetNamesOfAHeadAreTheUnionOfItsParts)
{
  auto part = [](const std::vector<std::string>& names)
  {
    vtkNew<vtkPolyData> poly;
    arrays::SetTargetNames(poly->GetFieldData(), names);
    return vtkSmartPointer<vtkPolyData>(poly);
  };
  vtkNew<vtkMultiBlockDataSet> head;
  head->SetNumberOfBlocks(4);
  head->SetBlock(0, part({ "neutral", "jawOpen" }));
  head->SetBlock(1, vtkNew<vtkPolyData>()); // a part without targets
  head->SetBlock(2, part({ "neutral", "eyeBlink_L", "jawOpen" }));
  head->SetBlock(3, part({ "neutral", "tongueOut" }));
  std::vector<std::string> targets;
  ASSERT_TRUE(arrays::GetFaceTargetNames(head, targets));
  EXPECT_EQ(targets, (std::vector<std::string>{ "jawOpen", "eyeBlink_L", "tongueOut" }));
  ASSERT_TRUE(arrays::GetFaceTargetNames(head->GetBlock(2), targets));
  EXPECT_EQ(targets, (std::vector<std::string>{ "eyeBlink_L", "jawOpen" }));
  EXPECT_FALSE(arrays::GetFaceTargetNames(head->GetBlock(1), targets));
  EXPECT_TRUE(targets.empty());
  EXPECT_FALSE(arrays::GetFaceTargetNames(nullptr, targets));
}

TEST(MorphTargetArrays, NamesOfTheConvention)
{
  EXPECT_EQ(arrays::ArrayName(0, Kind::Position), "target0_position");
  EXPECT_EQ(arrays::ArrayName(52, Kind::Normal), "target52_normal");
  EXPECT_TRUE(arrays::IsTargetArrayName("target12_tangent"));
  EXPECT_TRUE(arrays::IsTargetArrayName("target99999999999999_position"));
  EXPECT_FALSE(arrays::IsTargetArrayName("target_position"));
  EXPECT_FALSE(arrays::IsTargetArrayName("targetX_position"));
  EXPECT_FALSE(arrays::IsTargetArrayName("target3"));
  EXPECT_FALSE(arrays::IsTargetArrayName("Normals"));
  EXPECT_FALSE(arrays::IsTargetArrayName(nullptr));
}

TEST(MorphTargetArrays, ReadsWhatVtkGLTFReaderBuildsForTheDefaultFace)
{
  ASSERT_TRUE(std::filesystem::exists(DefaultFace)) << DefaultFace;
  vtkSmartPointer<vtkPolyData> poly = ReadWithVtkGLTFReader(DefaultFace);
  ASSERT_NE(poly, nullptr);
  ASSERT_TRUE(arrays::HasTargets(poly));
  const size_t n = arrays::CountTargets(poly->GetPointData(), poly->GetNumberOfPoints());
  EXPECT_GT(n, 10u);
  const bool normals = poly->GetPointData()->GetArray("target0_normal") != nullptr &&
    poly->GetPointData()->GetNormals() != nullptr;

  const arrays::MeshFromVTK read = arrays::ToMorphMesh(poly, arrays::ReadOptions());
  EXPECT_EQ(read.Mesh.GetNumberOfTargets(), n + 1);
  // vtkGLTFReader gives no names: the convention's defaults, glTF's target<k>.
  EXPECT_EQ(read.Mesh.GetTargetNames(), morphnode::DefaultTargetNames(n + 1));
  ExpectMeshHoldsTheArrays(poly, read.Mesh, normals);

  // vtkMorphTargetReader on the same file: the same deltas, and the names from the file.
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(DefaultFace.c_str());
  reader->SetMeshIndex(0); // the head's skin, the first mesh vtkGLTFReader gives too
  reader->Update();
  const arrays::MeshFromVTK named = arrays::ToMorphMesh(reader->GetOutput(), arrays::ReadOptions());
  ASSERT_EQ(named.Mesh.GetNumberOfTargets(), n + 1);
  for (size_t t = 1; t <= n; ++t)
  {
    EXPECT_EQ(named.Mesh.GetTargetNames()[t], reader->GetTargetName(static_cast<int>(t)));
    EXPECT_EQ(Dense(std::get<MorphAttribute<float>>(named.Mesh.GetAttribute(0)), t),
      Dense(std::get<MorphAttribute<float>>(read.Mesh.GetAttribute(0)), t))
      << named.Mesh.GetTargetNames()[t];
  }
}

TEST(MorphTargetArrays, ReadsWhatVtkGLTFReaderBuildsForTheIctFace)
{
  if (!std::filesystem::exists(IctFace))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctFace;
  }
  vtkSmartPointer<vtkPolyData> poly = ReadWithVtkGLTFReader(IctFace);
  ASSERT_NE(poly, nullptr);
  EXPECT_EQ(poly->GetNumberOfPoints(), 11248);
  arrays::ReadOptions options;
  options.Triangles = true;
  const arrays::MeshFromVTK read = arrays::ToMorphMesh(poly, options);
  EXPECT_EQ(read.Mesh.GetNumberOfTargets(), 54u);
  EXPECT_EQ(read.Mesh.GetNumberOfTriangles(), 22288u);
  EXPECT_EQ(read.TargetArrays.size(),
    53u * (poly->GetPointData()->GetArray("target0_normal") ? 2u : 1u) +
      (poly->GetPointData()->GetArray("target0_tangent") ? 53u : 0u));
  ExpectMeshHoldsTheArrays(poly, read.Mesh,
    poly->GetPointData()->GetArray("target0_normal") && poly->GetPointData()->GetNormals());
}

TEST(MorphTargetArrays, MorphMeshRoundTripsExactlyInFloat)
{
  ExpectRoundTrip<float>();
}

TEST(MorphTargetArrays, MorphMeshRoundTripsExactlyInDouble)
{
  ExpectRoundTrip<double>();
}

TEST(MorphTargetArrays, TargetArraysInTheRequestedTypes)
{
  const MorphMesh mesh = MakeMesh<double>();
  vtkNew<vtkPointData> pd;
  arrays::AddTargetArrays(mesh, pd, VTK_FLOAT, VTK_DOUBLE);
  ASSERT_EQ(pd->GetNumberOfArrays(), 6);
  EXPECT_EQ(pd->GetArray("target1_position")->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(pd->GetArray("target1_normal")->GetDataType(), VTK_DOUBLE);
  EXPECT_FLOAT_EQ(static_cast<float>(pd->GetArray("target1_position")->GetComponent(1, 0)), -0.4f);
  arrays::RemoveTargetArrays(pd);
  EXPECT_EQ(pd->GetNumberOfArrays(), 0);
}

TEST(MorphTargetArrays, ConvertsArraysOfAnyType)
{
  const std::vector<double> values = { -1.5, 0.25, 2.5, 254.5, 1e6, -0.0 };
  // float and double arrays
  for (int type : { VTK_FLOAT, VTK_DOUBLE })
  {
    auto array = arrays::NewArray(type, "x", 2, 3, values.data());
    EXPECT_EQ(array->GetDataType(), type);
    EXPECT_STREQ(array->GetName(), "x");
    EXPECT_EQ(arrays::ToVector<double>(array), values);
  }
  // integer arrays: rounded to the nearest
  auto ints = arrays::NewArray(VTK_INT, "i", 1, 6, values.data());
  EXPECT_EQ(arrays::ToVector<double>(ints), (std::vector<double>{ -2, 0, 3, 255, 1e6, 0 }));
  // an array type outside the dispatch list goes through the generic path
  vtkNew<vtkSOADataArrayTemplate<double>> soa;
  soa->SetNumberOfComponents(2);
  soa->SetNumberOfTuples(3);
  arrays::CopyToArray(values.data(), soa);
  EXPECT_EQ(soa->GetTypedComponent(1, 1), values[3]);
  EXPECT_EQ(arrays::ToVector<double>(soa), values);
  const std::vector<float> asFloat = arrays::ToVector<float>(soa);
  EXPECT_EQ(asFloat[1], 0.25f);
  EXPECT_EQ(asFloat[4], 1e6f);
  // the mesh's attribute follows the neutral array's type; integers clamp to their range
  MorphMesh mesh(2);
  mesh.SetTargetNames({ "Neutral", "a" });
  vtkNew<vtkUnsignedCharArray> color;
  color->SetNumberOfComponents(3);
  color->SetNumberOfTuples(2);
  color->Fill(200);
  vtkNew<vtkUnsignedCharArray> brighter;
  brighter->SetNumberOfComponents(3);
  brighter->SetNumberOfTuples(2);
  brighter->Fill(250);
  arrays::AddAttribute(mesh, "Colors", AttributeRole::Color, color, { brighter }, false, 0.3);
  const auto& colors = std::get<MorphAttribute<double>>(mesh.GetAttribute(0));
  EXPECT_EQ(colors.GetNeutral()[0], 200.0);
  EXPECT_EQ(Dense(colors, 1)[0], 50.0);
  vtkNew<vtkUnsignedCharArray> shortArray;
  shortArray->SetNumberOfComponents(3);
  shortArray->SetNumberOfTuples(1);
  EXPECT_NE(ErrorOf(
              [&] {
                arrays::AddAttribute(
                  mesh, "Colors", AttributeRole::Color, color, { shortArray }, false, 0.3);
              })
              .find("target 1's array"),
    std::string::npos);
}

TEST(MorphTargetArrays, BadInputIsReported)
{
  auto good = [] { return arrays::ToPolyData(MakeMesh<float>()); };
  arrays::ReadOptions triangles;
  triangles.Triangles = true;
  auto message = [&](vtkPointSet* input, const arrays::ReadOptions& options = arrays::ReadOptions())
  { return ErrorOf([&] { arrays::ToMorphMesh(input, options); }); };
  EXPECT_EQ(message(good()), "(no error)");
  EXPECT_NE(message(nullptr).find("no input"), std::string::npos);
  vtkNew<vtkPolyData> empty;
  EXPECT_NE(message(empty).find("no points"), std::string::npos);
  {
    auto gap = good();
    gap->GetPointData()->GetArray("target1_position")->SetName("target5_position");
    EXPECT_NE(message(gap).find("'target5_position' is target 5, but only targets 0 to 0 have"),
      std::string::npos)
      << message(gap);
  }
  {
    auto wrong = good();
    wrong->GetPointData()->GetArray("target1_position")->SetNumberOfTuples(3);
    EXPECT_NE(
      message(wrong).find("'target1_position' must be numeric with 3 components and 4 tuples"),
      std::string::npos);
  }
  {
    auto text = good();
    vtkNew<vtkStringArray> strings;
    strings->SetName("target0_position");
    strings->SetNumberOfValues(4);
    text->GetPointData()->AddArray(strings);
    EXPECT_NE(message(text).find("must be numeric"), std::string::npos);
  }
  {
    auto names = good();
    vtkStringArray::SafeDownCast(names->GetFieldData()->GetAbstractArray("TargetNames"))
      ->InsertNextValue("extra");
    EXPECT_NE(message(names).find("'TargetNames' has 5 names for 4 targets"), std::string::npos);
  }
  {
    auto twice = good();
    vtkStringArray::SafeDownCast(twice->GetFieldData()->GetAbstractArray("TargetNames"))
      ->SetValue(2, "jawOpen");
    EXPECT_NE(message(twice).find("two targets are named 'jawOpen'"), std::string::npos);
  }
  {
    auto notStrings = good();
    notStrings->GetFieldData()->RemoveArray("TargetNames");
    vtkNew<vtkIntArray> numbers;
    numbers->SetName("TargetNames");
    notStrings->GetFieldData()->AddArray(numbers);
    EXPECT_NE(message(notStrings).find("must be a string array"), std::string::npos);
  }
  {
    auto quads = good();
    vtkNew<vtkCellArray> polys;
    const vtkIdType quad[4] = { 0, 1, 2, 3 };
    polys->InsertNextCell(4, quad);
    quads->SetPolys(polys);
    EXPECT_NE(message(quads, triangles).find("must be triangles"), std::string::npos);
    EXPECT_EQ(message(quads), "(no error)"); // triangles not asked for
    EXPECT_EQ(arrays::GetTriangles(quads, true), (std::vector<uint32_t>{ 0, 1, 2, 0, 2, 3 }));
  }
  {
    auto none = good();
    none->SetPolys(vtkNew<vtkCellArray>());
    EXPECT_NE(message(none, triangles).find("no triangles"), std::string::npos);
  }
  // A morphed attribute the convention cannot hold.
  MorphMesh mesh = MakeMesh<float>();
  {
    auto& uv = mesh.AddAttribute<float>("uv", AttributeRole::Generic, 2);
    const std::vector<float> zero(8, 0.0f), moved = { 1, 0, 0, 0, 0, 0, 0, 0 };
    uv.SetNeutral(zero.data());
    uv.AddRelativeTarget(moved.data(), 0.3);
    uv.AddRelativeTarget(zero.data(), 0.3);
    uv.AddRelativeTarget(zero.data(), 0.3);
  }
  EXPECT_NE(ErrorOf([&] { arrays::ToPolyData(mesh); }).find("'uv' is morphed by target 'jawOpen'"),
    std::string::npos);
}
