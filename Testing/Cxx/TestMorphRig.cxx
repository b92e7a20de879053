// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphRigFilter (semantic weights -> target weights) and vtkMorphRigBaker (rig shapes
// as targets): equality with morphnode::Rig, bake == expand through the morph node, error
// cases, the rig-reading policy and time passing through.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphRigBaker.h"
#include "vtkMorphRigFilter.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeTestUtilities.h"

#include "rig/Rig.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTableAlgorithm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

using morphnode_test::MessageCollector;

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
const std::string ArkitRig = std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json";
const std::string DefaultFace =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";

bool HaveIct()
{
  return static_cast<bool>(std::ifstream(IctGlb));
}

std::string TempFile(const std::string& name)
{
  const std::filesystem::path dir =
    std::filesystem::path(MORPHNODE_TEST_OUTPUT_DIR) / "TestMorphRig";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

void WriteFile(const std::string& path, const std::string& text)
{
  std::ofstream out(path, std::ios::trunc);
  out << text;
}

/// A table with one double column per (name, values).
vtkSmartPointer<vtkTable> MakeTable(const std::map<std::string, std::vector<double>>& columns)
{
  auto table = vtkSmartPointer<vtkTable>::New();
  for (const auto& c : columns)
  {
    vtkNew<vtkDoubleArray> a;
    a->SetName(c.first.c_str());
    for (double v : c.second)
    {
      a->InsertNextValue(v);
    }
    table->AddColumn(a);
  }
  return table;
}

/// Names (neutral first) as the rig declares its targets.
vtkSmartPointer<vtkStringArray> NamesWithNeutral(const std::vector<std::string>& targets)
{
  auto names = vtkSmartPointer<vtkStringArray>::New();
  names->InsertNextValue("Neutral");
  for (const auto& t : targets)
  {
    names->InsertNextValue(t);
  }
  return names;
}

vtkSmartPointer<vtkPolyData> ReadFace(const std::string& file)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetMeshIndex(0); // one mesh, one vtkPolyData
  reader->Update();
  auto face = vtkSmartPointer<vtkPolyData>::New();
  face->ShallowCopy(reader->GetOutput());
  return face;
}

/// Largest distance between corresponding points.
double MaxPointDifference(vtkPointSet* a, vtkPointSet* b)
{
  EXPECT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  double worst = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints() && i < b->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    worst = std::max(worst,
      std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
        (p[2] - q[2]) * (p[2] - q[2])));
  }
  return worst;
}

double Diagonal(vtkPointSet* a)
{
  double b[6];
  a->GetBounds(b);
  return std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
}

/// A temporal weights source: TIME_STEPS 0, 1, 2; column A = t / 2, column Clock = t.
/// Remembers the time it was asked for.
class TimedWeightsSource : public vtkTableAlgorithm
{
public:
  static TimedWeightsSource* New();
  vtkTypeMacro(TimedWeightsSource, vtkTableAlgorithm);
  double LastRequestedTime = -1.0;
  int Executions = 0;

protected:
  TimedWeightsSource() { this->SetNumberOfInputPorts(0); }
  int RequestInformation(
    vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    vtkInformation* info = out->GetInformationObject(0);
    const double steps[3] = { 0.0, 1.0, 2.0 };
    const double range[2] = { 0.0, 2.0 };
    info->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps, 3);
    info->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
    return 1;
  }
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    vtkInformation* info = out->GetInformationObject(0);
    double t = 0.0;
    if (info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      t = info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    }
    this->LastRequestedTime = t;
    ++this->Executions;
    vtkTable* table = vtkTable::GetData(out, 0);
    table->ShallowCopy(MakeTable({ { "A", { t / 2.0 } }, { "Clock", { t } } }));
    return 1;
  }
};
vtkStandardNewMacro(TimedWeightsSource);
} // namespace

// --- vtkMorphRigFilter -------------------------------------------------------------------

TEST(MorphRigFilter, ExpansionEqualsRigExpand)
{
  morphnode::Rig rig = morphnode::Rig::LoadFile(ArkitRig);
  const std::vector<std::string> targets = rig.GetDeclaredTargets();
  ASSERT_EQ(targets.size(), 53u);
  rig.Bind(targets);

  // Three rows, shapes from several sets, one alias (aa), a pass-through column, and a
  // column named after a face target (dropped: the expansion wins).
  const std::map<std::string, std::vector<double>> columns{ { "A", { 0.8, 0.0, 1.0 } },
    { "O", { 0.0, 0.5, 1.0 } }, { "EyesClosed", { 1.0, 0.25, 0.0 } },
    { "BrowsUp", { 0.3, 0.0, 0.7 } }, { "PP", { 0.0, 1.0, 0.0 } }, { "aa", { 0.0, 0.2, 1.0 } },
    { "HeadYaw", { 0.1, 0.2, 0.3 } }, { "jawOpen", { 0.9, 0.9, 0.9 } } };
  auto table = MakeTable(columns);

  vtkNew<vtkMorphRigFilter> filter;
  filter->SetInputData(table);
  filter->SetRigFileName(ArkitRig.c_str());
  filter->SetTargetNames(NamesWithNeutral(targets));
  MessageCollector* raw = MessageCollector::New();
  vtkSmartPointer<MessageCollector> messages;
  messages.TakeReference(raw);
  messages->Watch(filter);
  filter->Update();
  ASSERT_TRUE(messages->Errors.empty()) << messages->AllErrors();

  vtkTable* out = filter->GetOutput();
  ASSERT_EQ(out->GetNumberOfRows(), 3);
  ASSERT_EQ(out->GetNumberOfColumns(), 54); // 53 targets + HeadYaw
  for (size_t t = 0; t < targets.size(); ++t)
  {
    EXPECT_EQ(out->GetColumn(static_cast<vtkIdType>(t))->GetName(), targets[t]);
  }
  EXPECT_STREQ(out->GetColumn(53)->GetName(), "HeadYaw");
  EXPECT_EQ(filter->GetNumberOfShapes(), static_cast<int>(rig.GetNumberOfShapes()));
  EXPECT_STREQ(filter->GetShapeName(0), "EyesClosed");

  int nonZero = 0;
  for (vtkIdType r = 0; r < 3; ++r)
  {
    std::map<std::string, double> named;
    for (const auto& c : columns)
    {
      if (rig.FindShape(c.first) >= 0)
      {
        named[c.first] = c.second[static_cast<size_t>(r)];
      }
    }
    const std::vector<double> expected = rig.Expand(named);
    for (size_t t = 0; t < targets.size(); ++t)
    {
      const double got = out->GetValueByName(r, targets[t].c_str()).ToDouble();
      EXPECT_DOUBLE_EQ(got, expected[t]) << "row " << r << " target " << targets[t];
      nonZero += got != 0.0;
    }
    EXPECT_DOUBLE_EQ(out->GetValueByName(r, "HeadYaw").ToDouble(), 0.1 * (r + 1));
  }
  EXPECT_GT(nonZero, 20);
  // Row 2: A + aa + O at full weight asks for jawOpen 1.45: clamped to 1.
  EXPECT_DOUBLE_EQ(out->GetValueByName(2, "jawOpen").ToDouble(), 1.0);
  EXPECT_DOUBLE_EQ(out->GetValueByName(0, "eyeBlink_L").ToDouble(), 1.0);

  filter->PassOtherColumnsOff();
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 53);
  EXPECT_EQ(filter->GetOutput()->GetColumnByName("HeadYaw"), nullptr);

  std::ostringstream print;
  filter->Print(print);
  EXPECT_NE(print.str().find("RigFileName: " + ArkitRig), std::string::npos);
  EXPECT_NE(print.str().find("PassOtherColumns: Off"), std::string::npos);
}

TEST(MorphRigFilter, NamesFromTheFaceOnPort1DriveTheMorphNode)
{
  if (!HaveIct())
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctGlb;
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->SetMeshIndex(0); // one mesh, one vtkPolyData

  vtkNew<vtkMorphRigFilter> rigFilter;
  rigFilter->SetInputData(MakeTable({ { "O", { 0.7 } }, { "MouthSmile", { 0.4 } } }));
  rigFilter->SetFaceConnection(reader->GetOutputPort());
  rigFilter->SetRigFileName(ArkitRig.c_str());

  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightsConnection(rigFilter->GetOutputPort());
  morph->SetWeightModeToRelative();
  morph->Update();
  vtkTable* weights = rigFilter->GetOutput();
  ASSERT_EQ(weights->GetNumberOfColumns(), 53);
  EXPECT_STREQ(weights->GetColumn(0)->GetName(), "browDown_L");

  morphnode::Rig rig = morphnode::Rig::LoadFile(ArkitRig);
  rig.Bind(rig.GetDeclaredTargets());
  const std::vector<double> expected = rig.Expand({ { "O", 0.7 }, { "MouthSmile", 0.4 } });
  int active = 0;
  for (int i = 1; i < morph->GetNumberOfTargets(); ++i)
  {
    const std::string name = morph->GetTargetName(i);
    const auto& bound = rig.GetBoundTargetNames();
    const size_t k =
      static_cast<size_t>(std::find(bound.begin(), bound.end(), name) - bound.begin());
    ASSERT_LT(k, bound.size()) << name;
    EXPECT_NEAR(morph->GetEffectiveWeight(i), expected[k], 1e-12) << name;
    active += expected[k] != 0.0;
  }
  EXPECT_EQ(morph->GetActiveTargetCount(), active);
  EXPECT_GT(active, 3);
}

TEST(MorphRigFilter, ErrorsGiveAnEmptyTable)
{
  morphnode::Rig rig = morphnode::Rig::LoadFile(ArkitRig);
  std::vector<std::string> targets = rig.GetDeclaredTargets();

  vtkNew<vtkMorphRigFilter> filter;
  filter->SetInputData(MakeTable({ { "A", { 0.5 } } }));
  filter->SetTargetNames(NamesWithNeutral(targets));
  vtkSmartPointer<MessageCollector> messages;
  messages.TakeReference(MessageCollector::New());
  messages->Watch(filter);

  // No rig file.
  filter->Update();
  EXPECT_TRUE(messages->HasError("no rig file")) << messages->AllErrors();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 0);

  // Unreadable rig.
  messages->Clear();
  filter->SetRigFileName(TempFile("does-not-exist.json").c_str());
  filter->Update();
  EXPECT_TRUE(messages->HasError("does-not-exist.json")) << messages->AllErrors();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 0);

  // Invalid JSON.
  messages->Clear();
  const std::string broken = TempFile("broken.json");
  WriteFile(broken, "{ \"name\": \"x\", \"shapes\": { \"A\": {\"jawOpen\": \"lots\"} } }");
  filter->SetRigFileName(broken.c_str());
  filter->Update();
  EXPECT_FALSE(messages->Errors.empty());
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 0);

  // The rig names a target the face lacks (jawOpen removed from the face).
  messages->Clear();
  filter->SetRigFileName(ArkitRig.c_str());
  targets.erase(std::find(targets.begin(), targets.end(), "jawOpen"));
  filter->SetTargetNames(NamesWithNeutral(targets));
  filter->Update();
  EXPECT_TRUE(messages->HasError("jawOpen")) << messages->AllErrors();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 0);

  // NaN and infinite weights.
  messages->Clear();
  filter->SetTargetNames(NamesWithNeutral(rig.GetDeclaredTargets()));
  filter->SetInputData(MakeTable({ { "A", { 0.5, std::numeric_limits<double>::quiet_NaN() } } }));
  filter->Update();
  EXPECT_TRUE(messages->HasError("not finite")) << messages->AllErrors();
  EXPECT_TRUE(messages->HasError("row 1")) << messages->AllErrors();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 0);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfRows(), 0);

  // A non-numeric shape column.
  messages->Clear();
  vtkNew<vtkTable> strings;
  vtkNew<vtkStringArray> text;
  text->SetName("O");
  text->InsertNextValue("half");
  strings->AddColumn(text);
  filter->SetInputData(strings);
  filter->Update();
  EXPECT_TRUE(messages->HasError("'O'")) << messages->AllErrors();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 0);

  // A face on port 1 without TargetNames.
  messages->Clear();
  filter->SetInputData(MakeTable({ { "A", { 0.5 } } }));
  vtkNew<vtkPolyData> anonymous;
  filter->SetInputData(1, anonymous);
  filter->Update();
  EXPECT_TRUE(messages->HasError("TargetNames")) << messages->AllErrors();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 0);

  // And it recovers.
  messages->Clear();
  filter->SetInputConnection(1, nullptr);
  filter->Update();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 53);
}

TEST(MorphRigFilter, RigIsReadOnlyWhenTheFileNameChangesOrOnModified)
{
  const std::string rigFile = TempFile("tiny.json");
  const std::string otherFile = TempFile("tiny2.json");
  WriteFile(rigFile, R"({"name": "tiny", "shapes": {"Up": {"a": 0.5, "b": 0.25}}})");
  WriteFile(otherFile, R"({"name": "tiny2", "shapes": {"Up": {"a": 0.1}}})");

  vtkNew<vtkStringArray> names;
  for (const char* n : { "Neutral", "a", "b" })
  {
    names->InsertNextValue(n);
  }
  auto table = MakeTable({ { "Up", { 1.0 } } });
  vtkNew<vtkMorphRigFilter> filter;
  filter->SetInputData(table);
  filter->SetTargetNames(names);
  filter->SetRigFileName(rigFile.c_str());
  filter->Update();
  EXPECT_DOUBLE_EQ(filter->GetOutput()->GetValueByName(0, "a").ToDouble(), 0.5);
  const vtkMTimeType first = filter->GetOutput()->GetMTime();

  // The file changes on disk: a re-execution caused upstream keeps the rig read before.
  WriteFile(rigFile, R"({"name": "tiny", "shapes": {"Up": {"a": 0.75, "b": 0.25}}})");
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetMTime(), first); // nothing changed: no execution
  vtkDoubleArray::SafeDownCast(table->GetColumnByName("Up"))->SetValue(0, 0.5);
  table->Modified();
  filter->Update();
  EXPECT_GT(filter->GetOutput()->GetMTime(), first);
  EXPECT_DOUBLE_EQ(filter->GetOutput()->GetValueByName(0, "a").ToDouble(), 0.25);

  // Modified() re-reads it.
  filter->Modified();
  filter->Update();
  EXPECT_DOUBLE_EQ(filter->GetOutput()->GetValueByName(0, "a").ToDouble(), 0.375);

  // So does a new file name, and setting the same name does not modify the filter.
  const vtkMTimeType before = filter->GetMTime();
  filter->SetRigFileName(rigFile.c_str());
  EXPECT_EQ(filter->GetMTime(), before);
  filter->SetRigFileName(otherFile.c_str());
  EXPECT_GT(filter->GetMTime(), before);
  filter->Update();
  EXPECT_DOUBLE_EQ(filter->GetOutput()->GetValueByName(0, "a").ToDouble(), 0.05);
  EXPECT_DOUBLE_EQ(filter->GetOutput()->GetValueByName(0, "b").ToDouble(), 0.0);
}

TEST(MorphRigFilter, TimePassesThroughPort0)
{
  vtkNew<TimedWeightsSource> source;
  vtkNew<vtkMorphRigFilter> filter;
  filter->SetInputConnection(source->GetOutputPort());
  filter->SetRigFileName(ArkitRig.c_str());
  morphnode::Rig rig = morphnode::Rig::LoadFile(ArkitRig);
  rig.Bind(rig.GetDeclaredTargets());
  // No names given: the rig's declared targets are used.

  filter->UpdateInformation();
  vtkInformation* outInfo = filter->GetOutputInformation(0);
  ASSERT_TRUE(outInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  EXPECT_EQ(outInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 3);
  ASSERT_TRUE(outInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_RANGE()));
  EXPECT_DOUBLE_EQ(outInfo->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE())[1], 2.0);

  for (double t : { 1.0, 2.0, 0.0 })
  {
    filter->UpdateTimeStep(t);
    EXPECT_DOUBLE_EQ(source->LastRequestedTime, t);
    vtkTable* out = filter->GetOutput();
    ASSERT_EQ(out->GetNumberOfRows(), 1);
    const std::vector<double> expected = rig.Expand({ { "A", t / 2.0 } });
    const int jaw = static_cast<int>(
      std::find(rig.GetBoundTargetNames().begin(), rig.GetBoundTargetNames().end(), "jawOpen") -
      rig.GetBoundTargetNames().begin());
    EXPECT_DOUBLE_EQ(out->GetValueByName(0, "jawOpen").ToDouble(), expected[jaw]);
    EXPECT_DOUBLE_EQ(out->GetValueByName(0, "Clock").ToDouble(), t);
    ASSERT_TRUE(out->GetInformation()->Has(vtkDataObject::DATA_TIME_STEP()));
    EXPECT_DOUBLE_EQ(out->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), t);
  }
  EXPECT_EQ(source->Executions, 3);
}

// --- vtkMorphRigBaker ---------------------------------------------------------------------

TEST(MorphRigBaker, BakedShapesEqualExpandedWeightsOnTheDefaultFace)
{
  // A small rig over the default face's own (paper) targets.
  const std::string rigFile = TempFile("default_face_rig.json");
  WriteFile(rigFile, R"({"name": "combos", "shapes": {
      "Surprise": {"BrowsUp": 0.8, "A": 0.4, "EyesClosed": 0.1},
      "Grin": {"MouthSmile": 1.0, "E": 0.3},
      "Rest": {},
      "Smirk": "Grin"},
      "sets": {"two": ["Grin", "Surprise"]}})");
  auto face = ReadFace(DefaultFace);
  ASSERT_GT(face->GetNumberOfPoints(), 0);
  auto* faceNames =
    vtkStringArray::SafeDownCast(face->GetFieldData()->GetAbstractArray("TargetNames"));
  ASSERT_NE(faceNames, nullptr);
  const vtkMTimeType faceTime = face->GetMTime();
  vtkDataArray* delta0 = face->GetPointData()->GetArray("target0_position");
  ASSERT_NE(delta0, nullptr);
  const double delta0Value = delta0->GetComponent(100, 1);

  vtkNew<vtkMorphRigBaker> baker;
  baker->SetInputData(face);
  baker->SetRigFileName(rigFile.c_str());
  baker->Update();
  vtkPointSet* baked = baker->GetOutput();
  auto* names =
    vtkStringArray::SafeDownCast(baked->GetFieldData()->GetAbstractArray("TargetNames"));
  ASSERT_NE(names, nullptr);
  ASSERT_EQ(names->GetNumberOfValues(), 5);
  EXPECT_EQ(names->GetValue(0), "Neutral");
  EXPECT_EQ(names->GetValue(1), "Surprise");
  EXPECT_EQ(names->GetValue(4), "Smirk");
  EXPECT_NE(baked->GetPointData()->GetArray("target3_position"), nullptr);
  EXPECT_NE(baked->GetPointData()->GetArray("target3_normal"), nullptr);
  EXPECT_EQ(baked->GetPointData()->GetArray("target4_position"), nullptr); // old ones gone
  EXPECT_EQ(
    baked->GetPointData()->GetArray("target0_position")->GetDataType(), delta0->GetDataType());
  EXPECT_EQ(baked->GetNumberOfCells(), face->GetNumberOfCells());
  // The input is untouched.
  EXPECT_EQ(face->GetMTime(), faceTime);
  EXPECT_EQ(face->GetPointData()->GetArray("target0_position"), delta0);
  EXPECT_EQ(delta0->GetComponent(100, 1), delta0Value);
  EXPECT_EQ(
    vtkStringArray::SafeDownCast(face->GetFieldData()->GetAbstractArray("TargetNames")), faceNames);
  EXPECT_EQ(faceNames->GetNumberOfValues(), 13);

  // Shape weight 1 on the baked face == the expanded weights on the original face.
  vtkNew<vtkMorphNodeFilter> viaBake;
  viaBake->SetInputData(baked);
  viaBake->SetWeightModeToRelative();
  vtkNew<vtkMorphRigFilter> expand;
  expand->SetRigFileName(rigFile.c_str());
  expand->SetTargetNames(faceNames);
  vtkNew<vtkMorphNodeFilter> viaExpand;
  viaExpand->SetInputData(face);
  viaExpand->SetWeightsConnection(expand->GetOutputPort());
  viaExpand->SetWeightModeToRelative();
  const double diagonal = Diagonal(face);
  for (const char* shape : { "Surprise", "Grin", "Rest", "Smirk" })
  {
    viaBake->ResetWeights();
    viaBake->SetWeightByName(shape, 1.0);
    viaBake->Update();
    expand->SetInputData(MakeTable({ { shape, { 1.0 } } }));
    viaExpand->Update();
    const double diff = MaxPointDifference(viaBake->GetOutput(), viaExpand->GetOutput());
    EXPECT_LT(diff, 1e-6 * diagonal) << shape;
    const double moved = MaxPointDifference(viaBake->GetOutput(), face);
    if (std::string(shape) == "Rest")
    {
      EXPECT_EQ(moved, 0.0);
    }
    else
    {
      EXPECT_GT(moved, 1e-3 * diagonal) << shape;
    }
  }

  // A set, then an explicit list (wins over the set).
  baker->SetShapeSet("two");
  baker->Update();
  names = vtkStringArray::SafeDownCast(
    baker->GetOutput()->GetFieldData()->GetAbstractArray("TargetNames"));
  ASSERT_EQ(names->GetNumberOfValues(), 3);
  EXPECT_EQ(names->GetValue(1), "Grin");
  vtkNew<vtkStringArray> list;
  list->InsertNextValue("Smirk");
  baker->SetShapeNames(list);
  baker->Update();
  names = vtkStringArray::SafeDownCast(
    baker->GetOutput()->GetFieldData()->GetAbstractArray("TargetNames"));
  ASSERT_EQ(names->GetNumberOfValues(), 2);
  EXPECT_EQ(names->GetValue(1), "Smirk");
  std::ostringstream print;
  baker->Print(print);
  EXPECT_NE(print.str().find("ShapeSet: two"), std::string::npos);
  EXPECT_NE(print.str().find("ShapeNames: Smirk"), std::string::npos);
}

TEST(MorphRigBaker, PaperShapesOnTheIctFaceEqualExpandPlusMorph)
{
  if (!HaveIct())
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctGlb;
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->SetMeshIndex(0); // one mesh, one vtkPolyData
  vtkNew<vtkMorphRigBaker> baker;
  baker->SetInputConnection(reader->GetOutputPort());
  baker->SetRigFileName(ArkitRig.c_str());
  baker->SetShapeSet("paper");
  baker->Update();
  vtkPointSet* baked = baker->GetOutput();
  auto* names =
    vtkStringArray::SafeDownCast(baked->GetFieldData()->GetAbstractArray("TargetNames"));
  ASSERT_NE(names, nullptr);
  ASSERT_EQ(names->GetNumberOfValues(), 13);
  const char* paper[13] = { "Neutral", "EyesClosed", "BrowsUp", "S", "F", "BrowsFright",
    "BrowsAngry", "L", "E", "A", "MouthSmile", "MouthSad", "O" };
  for (int i = 0; i < 13; ++i)
  {
    EXPECT_EQ(names->GetValue(i), paper[i]);
  }
  EXPECT_EQ(baked->GetNumberOfPoints(), 11248);
  EXPECT_EQ(baked->GetPointData()->GetArray("target12_position"), nullptr);
  EXPECT_NE(baked->GetPointData()->GetArray("target11_normal"), nullptr);
  EXPECT_EQ(vtkStringArray::SafeDownCast(
              reader->GetOutput()->GetFieldData()->GetAbstractArray("TargetNames"))
              ->GetNumberOfValues(),
    54);

  vtkNew<vtkMorphNodeFilter> viaBake;
  viaBake->SetInputConnection(baker->GetOutputPort());
  viaBake->SetWeightModeToRelative();
  vtkNew<vtkMorphRigFilter> expand;
  expand->SetRigFileName(ArkitRig.c_str());
  expand->SetFaceConnection(reader->GetOutputPort());
  vtkNew<vtkMorphNodeFilter> viaExpand;
  viaExpand->SetInputConnection(reader->GetOutputPort());
  viaExpand->SetWeightsConnection(expand->GetOutputPort());
  viaExpand->SetWeightModeToRelative();
  const double diagonal = Diagonal(reader->GetOutput());
  for (int i = 1; i < 13; ++i)
  {
    viaBake->ResetWeights();
    viaBake->SetWeightByName(paper[i], 1.0);
    viaBake->Update();
    expand->SetInputData(MakeTable({ { paper[i], { 1.0 } } }));
    viaExpand->Update();
    const double diff = MaxPointDifference(viaBake->GetOutput(), viaExpand->GetOutput());
    EXPECT_LT(diff, 1e-5 * diagonal) << paper[i] << ": " << diff;
    EXPECT_GT(MaxPointDifference(viaBake->GetOutput(), reader->GetOutput()), 1e-3 * diagonal)
      << paper[i] << " does not move the face";
  }
  // A mix of shapes whose expansion stays inside [0, 1] is equal too.
  viaBake->ResetWeights();
  viaBake->SetWeightByName("O", 0.6);
  viaBake->SetWeightByName("BrowsUp", 0.5);
  viaBake->SetWeightByName("EyesClosed", 0.3);
  viaBake->Update();
  expand->SetInputData(
    MakeTable({ { "O", { 0.6 } }, { "BrowsUp", { 0.5 } }, { "EyesClosed", { 0.3 } } }));
  viaExpand->Update();
  EXPECT_LT(MaxPointDifference(viaBake->GetOutput(), viaExpand->GetOutput()), 1e-5 * diagonal);
}

TEST(MorphRigBaker, ErrorsGiveAnEmptyOutput)
{
  auto face = ReadFace(DefaultFace);
  vtkNew<vtkMorphRigBaker> baker;
  baker->SetInputData(face);
  vtkSmartPointer<MessageCollector> messages;
  messages.TakeReference(MessageCollector::New());
  messages->Watch(baker);

  baker->Update();
  EXPECT_TRUE(messages->HasError("no rig file")) << messages->AllErrors();
  EXPECT_EQ(baker->GetOutput()->GetNumberOfPoints(), 0);

  // The ARKit rig on a face with the paper's targets: names a target the face lacks.
  messages->Clear();
  baker->SetRigFileName(ArkitRig.c_str());
  baker->Update();
  EXPECT_FALSE(messages->Errors.empty());
  EXPECT_TRUE(messages->HasError("eyeBlink_L") || messages->HasError("target"))
    << messages->AllErrors();
  EXPECT_EQ(baker->GetOutput()->GetNumberOfPoints(), 0);

  // Unknown set, unknown shape.
  const std::string rigFile = TempFile("errors_rig.json");
  WriteFile(rigFile, R"({"name": "e", "shapes": {"Up": {"BrowsUp": 1.0}}})");
  baker->SetRigFileName(rigFile.c_str());
  messages->Clear();
  baker->SetShapeSet("nosuchset");
  baker->Update();
  EXPECT_TRUE(messages->HasError("nosuchset")) << messages->AllErrors();
  EXPECT_EQ(baker->GetOutput()->GetNumberOfPoints(), 0);
  messages->Clear();
  baker->SetShapeSet("");
  vtkNew<vtkStringArray> list;
  list->InsertNextValue("Down");
  baker->SetShapeNames(list);
  baker->Update();
  EXPECT_TRUE(messages->HasError("Down")) << messages->AllErrors();
  EXPECT_EQ(baker->GetOutput()->GetNumberOfPoints(), 0);

  // No relative targets.
  messages->Clear();
  baker->SetShapeNames(nullptr);
  vtkNew<vtkPolyData> plain;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  plain->SetPoints(points);
  baker->SetInputData(plain);
  baker->Update();
  EXPECT_TRUE(messages->HasError("target0_position")) << messages->AllErrors();
  EXPECT_EQ(baker->GetOutput()->GetNumberOfPoints(), 0);

  // Recovers.
  messages->Clear();
  baker->SetInputData(face);
  baker->Update();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_EQ(baker->GetOutput()->GetNumberOfPoints(), face->GetNumberOfPoints());
}

// Rig-aware optimization: the threshold methods decide per rig shape, so ARKit's PP keeps
// mouthClose with jawOpen (per target on the ICT head, mouthClose 0.08 fell under the adjusted
// threshold and jawOpen stayed: the lips parted), a small E beside it is pruned whole, and
// the bound is reported.
TEST(MorphRigFilter, OptimizerDecidesPerRigShape)
{
  if (!HaveIct())
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctGlb;
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->SetMeshIndex(0);
  vtkNew<vtkMorphRigFilter> rigFilter;
  rigFilter->SetInputData(MakeTable({ { "PP", { 1.0, 0.93 } }, { "E", { 0.0, 0.07 } } }));
  rigFilter->SetFaceConnection(reader->GetOutputPort());
  rigFilter->SetRigFileName(ArkitRig.c_str());
  rigFilter->SetThreshold(0.1);
  auto value = [&](const char* name, int row)
  {
    vtkDataArray* a = vtkDataArray::SafeDownCast(rigFilter->GetOutput()->GetColumnByName(name));
    return a ? a->GetComponent(row, 0) : -1.0;
  };
  for (int preset : { vtkMorphNodeFilter::OPTIMIZER_FIXED_MAXIMUM,
         vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING, vtkMorphNodeFilter::OPTIMIZER_ADJUSTED })
  {
    rigFilter->SetOptimizerPreset(preset);
    rigFilter->Update();
    ASSERT_EQ(rigFilter->GetOutput()->GetNumberOfRows(), 2);
    // PP alone: the whole shape, mouthClose with jawOpen.
    EXPECT_NEAR(value("mouthClose", 0), 0.08, 1e-12) << preset;
    EXPECT_NEAR(value("jawOpen", 0), 0.08, 1e-12) << preset;
    EXPECT_NEAR(value("mouthPress_L", 0), 0.45, 1e-12) << preset;
  }
  // With a little E beside it, the fixed threshold prunes E whole (its share of the weight
  // goes to PP: the neutral's weight is 0 here), not some of E's targets.
  rigFilter->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING);
  rigFilter->Update();
  EXPECT_NEAR(value("mouthClose", 1), 0.08, 1e-12);
  EXPECT_NEAR(value("jawOpen", 1), 0.08, 1e-12);
  EXPECT_EQ(value("mouthStretch_L", 1), 0.0);
  EXPECT_EQ(value("mouthSmile_L", 1), 0.0);
  EXPECT_EQ(rigFilter->GetLastActiveShapes(), 1);
  EXPECT_GT(rigFilter->GetLastErrorBound(), 0.0);
  // Off: the plain expansion, E's targets included.
  rigFilter->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_NONE);
  rigFilter->Update();
  EXPECT_NEAR(value("mouthStretch_L", 1), 0.07 * 0.4, 1e-12);
  EXPECT_EQ(rigFilter->GetLastErrorBound(), 0.0);
}

TEST(MorphRigFilter, OptimizerNeedsTheFacesGeometry)
{
  morphnode::Rig rig = morphnode::Rig::LoadFile(ArkitRig);
  vtkNew<vtkMorphRigFilter> filter;
  filter->SetInputData(MakeTable({ { "PP", { 1.0 } } }));
  filter->SetTargetNames(NamesWithNeutral(rig.GetDeclaredTargets()));
  filter->SetRigFileName(ArkitRig.c_str());
  filter->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_ADJUSTED);
  vtkSmartPointer<MessageCollector> messages;
  messages.TakeReference(MessageCollector::New());
  messages->Watch(filter);
  filter->Update();
  EXPECT_TRUE(messages->HasError("measures the shapes on the face's geometry"))
    << messages->AllErrors();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 0);
  // Off (the default), names alone are enough.
  filter->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_NONE);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfColumns(), 53);
}

// The face on port 1 names the targets, also for a rig without a "targets" list (its
// declared list used to replace the face's names: "no target names").
TEST(MorphRigFilter, FaceNamesWinOverTheRigsDeclaredList)
{
  const std::string rigFile = TempFile("undeclared.json");
  WriteFile(rigFile, R"({"name": "undeclared", "shapes": {"Open": {"A": 0.5, "O": 0.25}}})");
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(DefaultFace.c_str());
  reader->SetMeshIndex(0);
  vtkNew<vtkMorphRigFilter> filter;
  filter->SetInputData(MakeTable({ { "Open", { 1.0 } } }));
  filter->SetFaceConnection(reader->GetOutputPort());
  filter->SetRigFileName(rigFile.c_str());
  filter->Update();
  vtkTable* out = filter->GetOutput();
  ASSERT_EQ(out->GetNumberOfColumns(), 12);
  EXPECT_DOUBLE_EQ(vtkDataArray::SafeDownCast(out->GetColumnByName("A"))->GetComponent(0, 0), 0.5);
  EXPECT_DOUBLE_EQ(vtkDataArray::SafeDownCast(out->GetColumnByName("O"))->GetComponent(0, 0), 0.25);
}
