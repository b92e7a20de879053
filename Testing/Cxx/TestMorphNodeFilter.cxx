// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphNodeFilter: Java3D and glTF semantics, attributes, pipeline behaviour, bad input.
#include "vtkMorphNodeFilter.h"

#include "MorphNodeTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTableAlgorithm.h"
#include "vtkTrivialProducer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkWeakPointer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

using morphnode_test::MessageCollector;

namespace
{
// A quad of 4 points; `shift` moves every point by (shift, 2 shift, 0); attributes vary
// with `shift` so that blends are checkable by hand.
vtkSmartPointer<vtkPolyData> MakeQuad(double shift, bool attributes = true)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points; // float points, as most readers give
  const double base[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } };
  for (const auto& p : base)
  {
    points->InsertNextPoint(p[0] + shift, p[1] + 2 * shift, p[2]);
  }
  pd->SetPoints(points);
  vtkNew<vtkCellArray> polys;
  const vtkIdType quad[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, quad);
  pd->SetPolys(polys);
  vtkNew<vtkIntArray> cellIds;
  cellIds->SetName("CellId");
  cellIds->InsertNextValue(42);
  pd->GetCellData()->AddArray(cellIds);
  if (!attributes)
  {
    return pd;
  }
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("Temperature");
  for (int i = 0; i < 4; ++i)
  {
    // Neutral normals +Z; shifted targets tilt them to +X.
    normals->InsertNextTuple3(shift != 0.0 ? 1.0 : 0.0, 0.0, shift != 0.0 ? 0.0 : 1.0);
    tcoords->InsertNextTuple2(0.25 * i + shift, shift);
    colors->InsertNextTuple3(shift != 0.0 ? 250 : 10, 100, 0);
    temperature->InsertNextValue(20.0 + 10.0 * shift + i);
  }
  pd->GetPointData()->SetNormals(normals);
  pd->GetPointData()->SetTCoords(tcoords);
  pd->GetPointData()->SetScalars(colors);
  pd->GetPointData()->AddArray(temperature);
  return pd;
}

struct Rig
{
  vtkNew<vtkMorphNodeFilter> Filter;
  vtkNew<MessageCollector> Messages;
  std::vector<vtkSmartPointer<vtkPolyData>> Targets;

  explicit Rig(std::vector<vtkSmartPointer<vtkPolyData>> targets)
    : Targets(std::move(targets))
  {
    this->Messages->Watch(this->Filter);
    this->Messages->Watch(this->Filter->GetExecutive()); // its "returned failure" report
    for (auto& t : this->Targets)
    {
      this->Filter->AddInputData(0, t);
    }
  }
  vtkPolyData* Run()
  {
    this->Filter->Update();
    return vtkPolyData::SafeDownCast(this->Filter->GetOutput());
  }
};

std::vector<vtkSmartPointer<vtkPolyData>> ThreeQuads()
{
  return { MakeQuad(0.0), MakeQuad(1.0), MakeQuad(2.0) };
}

/// A temporal source of one-row weight tables: at time t, target0 = t / 10.
class RampWeightsSource : public vtkTableAlgorithm
{
public:
  static RampWeightsSource* New();
  vtkTypeMacro(RampWeightsSource, vtkTableAlgorithm);
  int Executions = 0;

protected:
  RampWeightsSource() { this->SetNumberOfInputPorts(0); }
  int RequestInformation(
    vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    vtkInformation* info = out->GetInformationObject(0);
    const double steps[] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10 };
    info->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps, 11);
    const double range[] = { 0, 10 };
    info->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
    return 1;
  }
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    ++this->Executions;
    vtkInformation* info = out->GetInformationObject(0);
    const double t = info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
      ? info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
      : 0.0;
    vtkTable* table = vtkTable::GetData(out);
    vtkNew<vtkDoubleArray> target0;
    target0->SetName("target0");
    target0->InsertNextValue(t / 10.0);
    vtkNew<vtkDoubleArray> yaw; // not a target: ignored
    yaw->SetName("HeadYaw");
    yaw->InsertNextValue(5.0);
    table->AddColumn(target0);
    table->AddColumn(yaw);
    return 1;
  }
};
vtkStandardNewMacro(RampWeightsSource);

double Field(vtkDataObject* pd, const char* name, int i = 0)
{
  auto* a = vtkDataArray::SafeDownCast(pd->GetFieldData()->GetAbstractArray(name));
  return a ? a->GetComponent(i, 0) : std::numeric_limits<double>::quiet_NaN();
}
} // namespace

TEST(MorphNodeFilter, DefaultWeightsShowTheNeutral)
{
  Rig rig(ThreeQuads());
  vtkPolyData* out = rig.Run();
  ASSERT_EQ(out->GetNumberOfPoints(), 4);
  double p[3];
  out->GetPoint(2, p);
  EXPECT_DOUBLE_EQ(p[0], 1.0);
  EXPECT_DOUBLE_EQ(p[1], 1.0);
  EXPECT_EQ(rig.Filter->GetNumberOfTargets(), 3);
  EXPECT_STREQ(rig.Filter->GetTargetName(0), "Neutral");
  EXPECT_STREQ(rig.Filter->GetTargetName(2), "target1");
  EXPECT_EQ(rig.Filter->GetActiveTargetCount(), 0);
  EXPECT_TRUE(rig.Messages->Errors.empty());
}

TEST(MorphNodeFilter, StrictModeIsJava3D)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeightModeToStrict();
  rig.Filter->SetWeight(0, 0.5);
  rig.Filter->SetWeight(2, 0.5);
  vtkPolyData* out = rig.Run();
  double p[3];
  out->GetPoint(0, p);
  // 0.5 * (0,0,0) + 0.5 * (2,4,0)
  EXPECT_NEAR(p[0], 1.0, 1e-6);
  EXPECT_NEAR(p[1], 2.0, 1e-6);

  rig.Filter->SetWeight(1, 0.2); // sum 1.2
  out = rig.Run();
  EXPECT_EQ(out->GetNumberOfPoints(), 0);
  EXPECT_TRUE(rig.Messages->HasError("sum to 1.2")) << rig.Messages->AllErrors();
}

// Java3D's Morph checks only that the weights sum to 1 within 1e-4; a negative neutral
// (expression weights summing above 1) or negative targets are accepted, in Strict as there.
TEST(MorphNodeFilter, StrictModeAcceptsNegativeWeightsSummingToOne)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeightModeToStrict();
  const double negativeTargets[3] = { 1.3, -0.1, -0.2 };
  for (int i = 0; i < 3; ++i)
  {
    rig.Filter->SetWeight(i, negativeTargets[i]);
  }
  EXPECT_EQ(rig.Filter->UpdateTimeStep(0.0), 1);
  double p[3];
  rig.Filter->GetOutput()->GetPoint(0, p);
  // -0.1 (1,2,0) - 0.2 (2,4,0)
  EXPECT_NEAR(p[0], -0.5, 1e-6);
  EXPECT_NEAR(p[1], -1.0, 1e-6);
  EXPECT_EQ(rig.Filter->GetEffectiveWeight(2), -0.2);

  const double negativeNeutral[3] = { -0.2, 0.7, 0.5 };
  for (int i = 0; i < 3; ++i)
  {
    rig.Filter->SetWeight(i, negativeNeutral[i]);
  }
  EXPECT_EQ(rig.Filter->UpdateTimeStep(0.0), 1);
  rig.Filter->GetOutput()->GetPoint(0, p);
  // 0.7 (1,2,0) + 0.5 (2,4,0)
  EXPECT_NEAR(p[0], 1.7, 1e-6);
  EXPECT_NEAR(p[1], 3.4, 1e-6);
  EXPECT_EQ(rig.Filter->GetActiveTargetCount(), 2);
  EXPECT_TRUE(rig.Messages->Errors.empty()) << rig.Messages->AllErrors();

  // Off by 2e-4: refused as Java3D refuses it.
  rig.Filter->SetWeight(2, 0.5002);
  EXPECT_EQ(rig.Filter->UpdateTimeStep(0.0), 0);
  EXPECT_EQ(rig.Filter->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_TRUE(rig.Messages->HasError("sum to 1.0002")) << rig.Messages->AllErrors();

  // Normalize still refuses negative weights.
  rig.Filter->SetWeight(2, 0.5);
  rig.Filter->SetWeightModeToNormalize();
  EXPECT_EQ(rig.Filter->UpdateTimeStep(0.0), 0);
  EXPECT_TRUE(rig.Messages->HasError("negative")) << rig.Messages->AllErrors();
}

TEST(MorphNodeFilter, OptimizerPresets)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(0, 0.55);
  rig.Filter->SetWeight(1, 0.4);
  rig.Filter->SetWeight(2, 0.05);
  rig.Filter->SetThreshold(0.1);
  rig.Filter->SetMaxVertexError(0.5);
  EXPECT_EQ(rig.Filter->GetOptimizerPreset(), vtkMorphNodeFilter::OPTIMIZER_CUSTOM);
  EXPECT_STREQ(rig.Filter->GetOptimizerPresetAsString(), "custom");

  // fixed-maximum: the threshold, pruned weight to the largest (the neutral's 0.55).
  rig.Filter->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_FIXED_MAXIMUM);
  EXPECT_EQ(rig.Filter->GetRedistributionStrategy(), vtkMorphNodeFilter::MAXIMUM);
  EXPECT_FALSE(rig.Filter->GetAdjustThreshold());
  rig.Run();
  EXPECT_NEAR(rig.Filter->GetEffectiveWeight(0), 0.6, 1e-12);
  EXPECT_EQ(rig.Filter->GetEffectiveWeight(2), 0.0);
  EXPECT_STREQ(rig.Filter->GetOptimizerPresetAsString(), "fixed-maximum");

  // none: the threshold is kept but unused, so is the error bound.
  rig.Filter->SetOptimizerPresetByName("none");
  EXPECT_EQ(rig.Filter->GetOptimizerPreset(), vtkMorphNodeFilter::OPTIMIZER_NONE);
  rig.Run();
  EXPECT_EQ(rig.Filter->GetEffectiveWeight(2), 0.05);
  EXPECT_EQ(rig.Filter->GetActiveTargetCount(), 2);
  EXPECT_EQ(rig.Filter->GetThreshold(), 0.1);

  // error-bounded (any case): MaxVertexError, pruned weight to the neutral. Target 2
  // costs 0.05 |(2,4,0)| = 0.22 <= 0.5, target 1 0.4 |(1,2,0)| = 0.89 > 0.5.
  rig.Filter->SetOptimizerPresetByName("Error-Bounded");
  EXPECT_EQ(rig.Filter->GetOptimizerPreset(), vtkMorphNodeFilter::OPTIMIZER_ERROR_BOUNDED);
  EXPECT_EQ(rig.Filter->GetRedistributionStrategy(), vtkMorphNodeFilter::NEUTRAL);
  rig.Run();
  EXPECT_EQ(rig.Filter->GetEffectiveWeight(2), 0.0);
  EXPECT_EQ(rig.Filter->GetEffectiveWeight(1), 0.4);
  EXPECT_NEAR(rig.Filter->GetEffectiveWeight(0), 0.6, 1e-12);
  EXPECT_LE(rig.Filter->GetErrorBound(), 0.5);

  // adjusted, by number: th_adj = th_fix (1 - dist_norm); target 2 has dist_norm 1.
  rig.Filter->SetOptimizerPresetByName("3");
  EXPECT_EQ(rig.Filter->GetOptimizerPreset(), vtkMorphNodeFilter::OPTIMIZER_ADJUSTED);
  EXPECT_TRUE(rig.Filter->GetAdjustThreshold());
  EXPECT_EQ(rig.Filter->GetRedistributionStrategy(), vtkMorphNodeFilter::REMAINING);
  rig.Run();
  EXPECT_EQ(rig.Filter->GetEffectiveWeight(2), 0.05);

  // An unknown name is an error and changes nothing.
  rig.Filter->SetOptimizerPresetByName("fastest");
  EXPECT_TRUE(rig.Messages->HasError("unknown optimizer method")) << rig.Messages->AllErrors();
  EXPECT_EQ(rig.Filter->GetOptimizerPreset(), vtkMorphNodeFilter::OPTIMIZER_ADJUSTED);

  // An individual method setting switches to the individual settings, the preset's kept.
  rig.Filter->SetRedistributionStrategyToMaximum();
  EXPECT_EQ(rig.Filter->GetOptimizerPreset(), vtkMorphNodeFilter::OPTIMIZER_CUSTOM);
  EXPECT_TRUE(rig.Filter->GetAdjustThreshold());
  rig.Filter->SetOptimizerPresetByName("custom");
  EXPECT_EQ(rig.Filter->GetOptimizerPreset(), vtkMorphNodeFilter::OPTIMIZER_CUSTOM);

  // A preset already in effect does not modify the filter.
  rig.Filter->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING);
  const vtkMTimeType before = rig.Filter->GetMTime();
  rig.Filter->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING);
  rig.Filter->SetRedistributionStrategyToRemaining();
  EXPECT_EQ(rig.Filter->GetMTime(), before);
  EXPECT_EQ(rig.Filter->GetOptimizerPreset(), vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING);
}

// Java3D's geometries as the partitions of one vtkPartitionedDataSet: one connection, the
// same result as one connection per geometry; partitions with target arrays stay a head.
TEST(MorphNodeFilter, Java3DFormInOneConnection)
{
  Rig connections(ThreeQuads());
  vtkNew<vtkPartitionedDataSet> shapes;
  for (const auto& quad : ThreeQuads())
  {
    shapes->SetPartition(shapes->GetNumberOfPartitions(), quad);
  }
  vtkNew<vtkMorphNodeFilter> one;
  one->SetInputData(0, shapes);
  EXPECT_EQ(one->GetNumberOfTargets(), 3);
  for (vtkMorphNodeFilter* filter : { connections.Filter.Get(), one.Get() })
  {
    filter->SetWeightModeToStrict();
    filter->SetWeight(0, 0.25);
    filter->SetWeight(2, 0.75);
    filter->Update();
  }
  auto* expected = vtkPolyData::SafeDownCast(connections.Filter->GetOutputDataObject(0));
  auto* got = vtkPolyData::SafeDownCast(one->GetOutputDataObject(0));
  ASSERT_TRUE(expected && got) << one->GetOutputDataObject(0)->GetClassName();
  ASSERT_EQ(got->GetNumberOfPoints(), expected->GetNumberOfPoints());
  EXPECT_EQ(got->GetNumberOfPolys(), expected->GetNumberOfPolys());
  for (vtkIdType i = 0; i < got->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    got->GetPoint(i, a);
    expected->GetPoint(i, b);
    EXPECT_DOUBLE_EQ(a[0], b[0]);
    EXPECT_DOUBLE_EQ(a[1], b[1]);
  }
  EXPECT_STREQ(one->GetTargetName(2), "target1");
  EXPECT_EQ(one->GetActiveTargetCount(), 1);

  // A partition with target arrays: a head of parts, as before.
  vtkNew<vtkFloatArray> delta;
  delta->SetName("target0_position");
  delta->SetNumberOfComponents(3);
  delta->SetNumberOfTuples(4);
  delta->FillValue(0.5f);
  auto part = MakeQuad(0.0);
  part->GetPointData()->AddArray(delta);
  vtkNew<vtkPartitionedDataSet> head;
  head->SetPartition(0, part);
  vtkNew<vtkMorphNodeFilter> parts;
  parts->SetInputData(0, head);
  parts->SetWeight(1, 1.0);
  parts->Update();
  EXPECT_TRUE(vtkPartitionedDataSet::SafeDownCast(parts->GetOutputDataObject(0)));
}

TEST(MorphNodeFilter, NormalizeModeDividesBySum)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(0, 1.0);
  rig.Filter->SetWeight(1, 3.0);
  vtkPolyData* out = rig.Run();
  double p[3];
  out->GetPoint(0, p);
  EXPECT_NEAR(p[0], 0.75, 1e-6);
  EXPECT_NEAR(rig.Filter->GetEffectiveWeight(1), 0.75, 1e-12);
  EXPECT_NEAR(Field(out, "EffectiveWeights", 1), 0.75, 1e-12);
  EXPECT_EQ(Field(out, "ActiveTargetCount"), 1.0);
}

TEST(MorphNodeFilter, RelativeModeIsGLTF)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeightModeToRelative();
  rig.Filter->SetWeight(1, 0.5);
  rig.Filter->SetWeight(2, 0.5);
  vtkPolyData* out = rig.Run();
  double p[3];
  out->GetPoint(0, p);
  // neutral + 0.5 * (1,2,0) + 0.5 * (2,4,0): no sum-to-1 rule.
  EXPECT_NEAR(p[0], 1.5, 1e-6);
  EXPECT_NEAR(p[1], 3.0, 1e-6);
  EXPECT_NEAR(rig.Filter->GetEffectiveWeight(0), 0.0, 1e-12);
}

TEST(MorphNodeFilter, BlendsEveryAttributeKind)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(0, 0.5);
  rig.Filter->SetWeight(1, 0.5);
  vtkPolyData* out = rig.Run();
  vtkPointData* pd = out->GetPointData();
  ASSERT_NE(pd->GetNormals(), nullptr);
  ASSERT_NE(pd->GetTCoords(), nullptr);
  ASSERT_NE(pd->GetScalars(), nullptr);
  // Normals: halfway between +Z and +X, renormalized.
  double n[3];
  pd->GetNormals()->GetTuple(1, n);
  EXPECT_NEAR(n[0], std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(n[2], std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(vtkMath::Norm(n), 1.0, 1e-6);
  // Texture coordinates: plain blend.
  EXPECT_NEAR(pd->GetTCoords()->GetComponent(1, 0), 0.25 + 0.5, 1e-6);
  EXPECT_EQ(pd->GetTCoords()->GetNumberOfComponents(), 2);
  // Colours keep their type and are rounded: (10 + 250) / 2.
  EXPECT_TRUE(vtkUnsignedCharArray::SafeDownCast(pd->GetScalars()) != nullptr);
  EXPECT_EQ(pd->GetScalars()->GetComponent(0, 0), 130.0);
  // Other numeric arrays.
  ASSERT_NE(pd->GetArray("Temperature"), nullptr);
  EXPECT_NEAR(pd->GetArray("Temperature")->GetComponent(3, 0), 23.0 + 5.0, 1e-9);
  // Cells and topology shared from the neutral, not copied.
  EXPECT_EQ(out->GetPolys(), rig.Targets[0]->GetPolys());
  EXPECT_EQ(
    out->GetCellData()->GetArray("CellId"), rig.Targets[0]->GetCellData()->GetArray("CellId"));
}

TEST(MorphNodeFilter, ClampsColorsToTheirType)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeightModeToRelative();
  rig.Filter->SetWeight(1, 1.5); // 10 + 1.5 * 240 = 370 -> 255
  vtkPolyData* out = rig.Run();
  EXPECT_EQ(out->GetPointData()->GetScalars()->GetComponent(0, 0), 255.0);
}

TEST(MorphNodeFilter, ArraysNotOnAllTargetsPassThroughFromTheNeutral)
{
  auto targets = ThreeQuads();
  targets[2]->GetPointData()->RemoveArray("Temperature");
  Rig rig(targets);
  rig.Filter->SetWeight(0, 0.0);
  rig.Filter->SetWeight(1, 1.0);
  vtkPolyData* out = rig.Run();
  EXPECT_EQ(out->GetPointData()->GetArray("Temperature"),
    targets[0]->GetPointData()->GetArray("Temperature"));
}

TEST(MorphNodeFilter, ReExecutesWhenAndOnlyWhenNeeded)
{
  Rig rig(ThreeQuads());
  int executions = 0;
  vtkNew<vtkCallbackCommand> counter;
  counter->SetClientData(&executions);
  counter->SetCallback([](vtkObject*, unsigned long, void* c, void*) { ++*static_cast<int*>(c); });
  rig.Filter->AddObserver(vtkCommand::EndEvent, counter);
  rig.Run();
  EXPECT_EQ(executions, 1);
  rig.Run();
  EXPECT_EQ(executions, 1) << "a second Update without a change must not re-execute";
  rig.Filter->SetWeight(0, 1.0); // the value it already has
  rig.Run();
  EXPECT_EQ(executions, 1) << "setting an unchanged weight must not re-execute";
  rig.Filter->SetWeight(1, 0.3);
  rig.Run();
  EXPECT_EQ(executions, 2);
  rig.Filter->SetThreshold(0.2);
  rig.Run();
  EXPECT_EQ(executions, 3);
  rig.Targets[1]->GetPoints()->SetPoint(0, 9, 9, 9);
  rig.Targets[1]->Modified();
  rig.Run();
  EXPECT_EQ(executions, 4);
}

TEST(MorphNodeFilter, NeverModifiesItsInputs)
{
  auto targets = ThreeQuads();
  std::vector<vtkMTimeType> before;
  for (auto& t : targets)
  {
    before.push_back(t->GetMTime());
  }
  Rig rig(targets);
  rig.Filter->SetWeight(1, 0.7);
  rig.Filter->SetGenerateDistanceArrays(true);
  rig.Run();
  for (size_t i = 0; i < targets.size(); ++i)
  {
    EXPECT_EQ(targets[i]->GetMTime(), before[i]) << "target " << i;
    EXPECT_EQ(targets[i]->GetPointData()->GetNumberOfArrays(), 4) << "target " << i;
    EXPECT_EQ(targets[i]->GetFieldData()->GetNumberOfArrays(), 0) << "target " << i;
  }
  double p[3];
  targets[0]->GetPoint(0, p);
  EXPECT_EQ(p[0], 0.0);
}

TEST(MorphNodeFilter, ReusesItsOutputArraysOnlyWhenNobodyHoldsThem)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeightModeToRelative(); // point 1: x = 1 + w1
  rig.Filter->SetWeight(1, 0.5);
  vtkPolyData* out = rig.Run();
  vtkDataArray* points = out->GetPoints()->GetData();
  vtkDataArray* normals = out->GetPointData()->GetNormals();
  const vtkMTimeType pointsTime = points->GetMTime();

  // Nobody but the filter holds last step's arrays: they are written again in place (no
  // allocation per time step), and their MTime moves so renderers upload them again.
  rig.Filter->SetWeight(1, 0.25);
  out = rig.Run();
  EXPECT_EQ(out->GetPoints()->GetData(), points);
  EXPECT_EQ(out->GetPointData()->GetNormals(), normals);
  EXPECT_GT(points->GetMTime(), pointsTime);
  EXPECT_NEAR(out->GetPoint(1)[0], 1.0 + 0.25, 1e-6);

  // A snapshot kept downstream (a shallow copy, as a cache or a Python variable holds)
  // must not change when the filter runs again.
  vtkNew<vtkPolyData> snapshot;
  snapshot->ShallowCopy(out);
  rig.Filter->SetWeight(1, 1.0);
  out = rig.Run();
  EXPECT_NE(out->GetPoints()->GetData(), snapshot->GetPoints()->GetData());
  EXPECT_NE(out->GetPointData()->GetNormals(), snapshot->GetPointData()->GetNormals());
  EXPECT_NEAR(snapshot->GetPoint(1)[0], 1.25, 1e-6) << "the held snapshot changed";
  EXPECT_NEAR(out->GetPoint(1)[0], 2.0, 1e-6);
  EXPECT_NEAR(Field(snapshot, "EffectiveWeights", 1), 0.25, 1e-12);
  EXPECT_NEAR(Field(out, "EffectiveWeights", 1), 1.0, 1e-12);
}

// A renderer holds each frame's arrays until the next frame: the filter then writes the
// set before (which the renderer has let go of) instead of new arrays every frame, and
// never an array someone still holds, however long they hold it.
TEST(MorphNodeFilter, HeldFramesAlternateBetweenTwoSetsAndHeldArraysNeverChange)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeightModeToRelative(); // point 1: x = 1 + w1
  vtkNew<vtkPolyData> drawn;             // as a renderer's input holds the last frame
  std::vector<vtkWeakPointer<vtkDataArray>> points, normals;
  for (int frame = 0; frame < 6; ++frame)
  {
    rig.Filter->SetWeight(1, 0.1 * frame);
    vtkPolyData* out = rig.Run();
    ASSERT_NEAR(out->GetPoint(1)[0], 1.0 + 0.1 * frame, 1e-6) << "frame " << frame;
    points.emplace_back(out->GetPoints()->GetData());
    normals.emplace_back(out->GetPointData()->GetNormals());
    drawn->ShallowCopy(out);
  }
  for (int frame = 2; frame < 6; ++frame)
  {
    // Frame f wrote frame f-2's arrays: the same objects, kept alive by the filter.
    EXPECT_TRUE(points[frame - 2] && points[frame] == points[frame - 2]) << "frame " << frame;
    EXPECT_TRUE(normals[frame - 2] && normals[frame] == normals[frame - 2]) << "frame " << frame;
    EXPECT_NE(points[frame], points[frame - 1]) << "frame " << frame;
  }

  // Two frames held at once (the renderer's and a snapshot kept longer): neither changes,
  // whatever the filter writes next (points, normals and every other blended array).
  auto values = [](vtkPolyData* pd)
  {
    std::vector<double> v;
    for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    {
      v.insert(v.end(), pd->GetPoint(i), pd->GetPoint(i) + 3);
    }
    for (int a = 0; a < pd->GetPointData()->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* array = pd->GetPointData()->GetArray(a);
      for (vtkIdType t = 0; array && t < array->GetNumberOfTuples(); ++t)
      {
        for (int c = 0; c < array->GetNumberOfComponents(); ++c)
        {
          v.push_back(array->GetComponent(t, c));
        }
      }
    }
    return v;
  };
  vtkNew<vtkPolyData> kept;
  kept->ShallowCopy(drawn); // frame 5
  const std::vector<double> keptValues = values(kept);
  for (int frame = 6; frame < 10; ++frame)
  {
    const std::vector<double> drawnValues = values(drawn);
    rig.Filter->SetWeight(1, 0.1 * frame);
    vtkPolyData* out = rig.Run();
    EXPECT_NEAR(out->GetPoint(1)[0], 1.0 + 0.1 * frame, 1e-6) << "frame " << frame;
    EXPECT_EQ(values(drawn), drawnValues) << "the renderer's frame changed at frame " << frame;
    EXPECT_EQ(values(kept), keptValues) << "the kept frame changed at frame " << frame;
    drawn->ShallowCopy(out);
  }
}

TEST(MorphNodeFilter, OutputArraysKeepTheNeutralsOrderAndRoles)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(1, 0.5);
  for (int run = 0; run < 2; ++run) // the second run reuses the arrays
  {
    rig.Filter->SetWeight(2, 0.1 * run);
    vtkPointData* in = rig.Targets[0]->GetPointData();
    vtkPointData* out = rig.Run()->GetPointData();
    ASSERT_EQ(out->GetNumberOfArrays(), in->GetNumberOfArrays());
    for (int a = 0; a < in->GetNumberOfArrays(); ++a)
    {
      EXPECT_STREQ(out->GetArrayName(a), in->GetArrayName(a));
      EXPECT_EQ(out->IsArrayAnAttribute(a), in->IsArrayAnAttribute(a)) << in->GetArrayName(a);
    }
  }
}

TEST(MorphNodeFilter, NamesAndWeightsByName)
{
  auto targets = ThreeQuads();
  vtkNew<vtkStringArray> names;
  names->SetName("TargetNames");
  names->InsertNextValue("Neutral");
  names->InsertNextValue("O");
  names->InsertNextValue("A");
  targets[0]->GetFieldData()->AddArray(names);
  Rig rig(targets);
  rig.Filter->SetWeightByName("A", 1.0);
  rig.Filter->SetWeightByName("Neutral", 0.0);
  vtkPolyData* out = rig.Run();
  EXPECT_STREQ(rig.Filter->GetTargetName(2), "A");
  EXPECT_EQ(rig.Filter->GetTargetIndex("O"), 1);
  double p[3];
  out->GetPoint(0, p);
  EXPECT_NEAR(p[0], 2.0, 1e-6);
  EXPECT_EQ(rig.Filter->GetWeightByName("A"), 1.0);
  EXPECT_EQ(rig.Filter->GetWeight(2), 1.0);
}

TEST(MorphNodeFilter, GLTFFormWithRelativeTargetArrays)
{
  auto base = MakeQuad(0.0, false);
  for (int k = 0; k < 2; ++k)
  {
    vtkNew<vtkFloatArray> delta;
    delta->SetName(("target" + std::to_string(k) + "_position").c_str());
    delta->SetNumberOfComponents(3);
    for (int i = 0; i < 4; ++i)
    {
      delta->InsertNextTuple3(k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, i == 0 ? 1.0 : 0.0);
    }
    base->GetPointData()->AddArray(delta);
  }
  vtkNew<vtkMorphNodeFilter> filter;
  filter->SetInputData(base);
  filter->SetWeightModeToRelative();
  filter->SetWeight(1, 0.5);
  filter->SetWeight(2, 0.25);
  filter->Update();
  vtkPolyData* out = vtkPolyData::SafeDownCast(filter->GetOutput());
  EXPECT_EQ(filter->GetNumberOfTargets(), 3);
  EXPECT_STREQ(filter->GetTargetName(1), "target0");
  double p[3];
  out->GetPoint(0, p);
  EXPECT_NEAR(p[0], 0.5, 1e-6);
  EXPECT_NEAR(p[1], 0.25, 1e-6);
  EXPECT_NEAR(p[2], 0.75, 1e-6);
  // The target arrays are inputs, not output.
  EXPECT_EQ(out->GetPointData()->GetArray("target0_position"), nullptr);
}

TEST(MorphNodeFilter, WeightsFromATableAndTimeFlowThroughPort1)
{
  Rig rig(ThreeQuads());
  vtkNew<RampWeightsSource> ramp;
  rig.Filter->SetWeightsConnection(ramp->GetOutputPort());
  rig.Filter->UpdateInformation();
  vtkInformation* outInfo = rig.Filter->GetOutputInformation(0);
  ASSERT_TRUE(outInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  EXPECT_EQ(outInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 11);

  rig.Filter->UpdateTimeStep(4.0);
  vtkPolyData* out = vtkPolyData::SafeDownCast(rig.Filter->GetOutput());
  // target0 = 0.4 from the table; the neutral gets 1 - 0.4.
  EXPECT_NEAR(rig.Filter->GetEffectiveWeight(1), 0.4, 1e-12);
  EXPECT_NEAR(rig.Filter->GetEffectiveWeight(0), 0.6, 1e-12);
  double p[3];
  out->GetPoint(0, p);
  EXPECT_NEAR(p[0], 0.4, 1e-6);
  EXPECT_EQ(out->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), 4.0);

  rig.Filter->UpdateTimeStep(10.0);
  EXPECT_NEAR(rig.Filter->GetEffectiveWeight(1), 1.0, 1e-12);
  EXPECT_TRUE(rig.Messages->Errors.empty()) << rig.Messages->AllErrors();
}

TEST(MorphNodeFilter, OptimizerAndDistanceArrays)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(0, 0.55);
  rig.Filter->SetWeight(1, 0.4);
  rig.Filter->SetWeight(2, 0.05);
  rig.Filter->SetThreshold(0.1);
  rig.Filter->SetRedistributionStrategyToMaximum();
  rig.Filter->GenerateDistanceArraysOn();
  vtkPolyData* out = rig.Run();
  EXPECT_NEAR(rig.Filter->GetEffectiveWeight(0), 0.6, 1e-12);
  EXPECT_EQ(rig.Filter->GetEffectiveWeight(2), 0.0);
  EXPECT_EQ(rig.Filter->GetActiveTargetCount(), 1);
  // Target 2 moves every point by |(2,4,0)|; the bound is 0.05 * that.
  EXPECT_NEAR(rig.Filter->GetErrorBound(), 0.05 * std::sqrt(20.0), 1e-9);
  ASSERT_NE(out->GetPointData()->GetArray("AnimatedRegion"), nullptr);
  EXPECT_NEAR(
    out->GetPointData()->GetArray("AnimatedRegion")->GetComponent(0, 0), std::sqrt(20.0), 1e-5);
  ASSERT_NE(out->GetPointData()->GetArray("Distance_target0"), nullptr);
  EXPECT_NEAR(
    out->GetPointData()->GetArray("Distance_target0")->GetComponent(3, 0), std::sqrt(5.0), 1e-5);
  EXPECT_NEAR(rig.Filter->GetDistNorm()->GetValue(1), 0.5, 1e-9);
  EXPECT_NEAR(Field(out, "DistNorm", 2), 1.0, 1e-9);
}

TEST(MorphNodeFilter, DistanceArraysFollowTheTargetsNotTheWeights)
{
  Rig rig(ThreeQuads());
  rig.Filter->GenerateDistanceArraysOn();
  rig.Filter->SetWeight(1, 0.5);
  vtkDataArray* first = rig.Run()->GetPointData()->GetArray("Distance_target0");
  ASSERT_NE(first, nullptr);
  EXPECT_NEAR(first->GetComponent(0, 0), std::sqrt(5.0), 1e-6);
  // A new weight: the same distances, computed once per set of targets.
  rig.Filter->SetWeight(1, 0.75);
  EXPECT_EQ(rig.Run()->GetPointData()->GetArray("Distance_target0"), first);
  // A moved target: new distances.
  rig.Targets[1]->GetPoints()->SetPoint(0, 3, 4, 0);
  rig.Targets[1]->Modified();
  vtkDataArray* moved = rig.Run()->GetPointData()->GetArray("Distance_target0");
  ASSERT_NE(moved, nullptr);
  EXPECT_NEAR(moved->GetComponent(0, 0), 5.0, 1e-6);
  // Switched off: gone from the output.
  rig.Filter->GenerateDistanceArraysOff();
  EXPECT_EQ(rig.Run()->GetPointData()->GetArray("Distance_target0"), nullptr);
}

TEST(MorphNodeFilter, AcceptsAnyPointSet)
{
  vtkNew<vtkMorphNodeFilter> filter;
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> grids;
  for (double shift : { 0.0, 1.0 })
  {
    auto quad = MakeQuad(shift);
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    grid->SetPoints(quad->GetPoints());
    const vtkIdType ids[4] = { 0, 1, 2, 3 };
    grid->InsertNextCell(VTK_QUAD, 4, ids);
    grids.push_back(grid);
    filter->AddInputData(0, grid);
  }
  filter->SetWeight(1, 1.0);
  filter->SetWeight(0, 0.0);
  filter->Update();
  auto* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutput());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->GetNumberOfCells(), 1);
  EXPECT_NEAR(out->GetPoint(0)[0], 1.0, 1e-6);
}

// --- bad input: a clear error, an empty output, nothing lost ------------------------

struct BadInput : public ::testing::Test
{
  void ExpectError(Rig& rig, const std::string& fragment)
  {
    vtkPolyData* out = rig.Run();
    EXPECT_EQ(out->GetNumberOfPoints(), 0);
    EXPECT_TRUE(rig.Messages->HasError(fragment))
      << "expected an error containing '" << fragment << "', got:\n"
      << rig.Messages->AllErrors();
    EXPECT_EQ(rig.Filter->GetActiveTargetCount(), 0);
  }
};

TEST_F(BadInput, MismatchedPointCounts)
{
  auto targets = ThreeQuads();
  targets[2]->GetPoints()->InsertNextPoint(5, 5, 5);
  Rig rig(targets);
  ExpectError(rig, "target 2 has 5 points, the neutral has 4");
}

TEST_F(BadInput, NaNAndInfiniteWeights)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(1, std::numeric_limits<double>::quiet_NaN());
  ExpectError(rig, "weight 1 is nan");
  rig.Messages->Clear();
  rig.Filter->SetWeight(1, std::numeric_limits<double>::infinity());
  ExpectError(rig, "weight 1 is inf");
}

TEST_F(BadInput, NegativeWeightOutsideRelativeMode)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(1, -0.5);
  ExpectError(rig, "negative");
}

TEST_F(BadInput, IndexOutOfRange)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(7, 0.5);
  ExpectError(rig, "target 7, but the input has 3 targets");
}

TEST_F(BadInput, UnknownName)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeightByName("jawOpen", 0.5);
  ExpectError(rig, "no target has that name");
}

TEST_F(BadInput, NormalizeSumZero)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(0, 0.0);
  ExpectError(rig, "sum to 0");
}

TEST_F(BadInput, EmptyMesh)
{
  Rig rig({ vtkSmartPointer<vtkPolyData>::New() });
  ExpectError(rig, "no points");
}

TEST_F(BadInput, TargetArraysOfTheWrongSize)
{
  auto base = MakeQuad(0.0, false);
  vtkNew<vtkFloatArray> delta;
  delta->SetName("target0_position");
  delta->SetNumberOfComponents(3);
  delta->SetNumberOfTuples(3); // one short
  delta->FillValue(0.f);
  base->GetPointData()->AddArray(delta);
  Rig rig({ base });
  ExpectError(rig, "'target0_position' must be numeric with 3 components and 4 tuples");
}

TEST_F(BadInput, TargetNamesOfTheWrongCount)
{
  auto targets = ThreeQuads();
  vtkNew<vtkStringArray> names;
  names->SetName("TargetNames");
  names->InsertNextValue("Neutral");
  targets[0]->GetFieldData()->AddArray(names);
  Rig rig(targets);
  ExpectError(rig, "has 1 names for 3 targets");
}

// A failed update is a failure for the pipeline too: UpdateTimeStep() returns 0 and the
// output is empty, whatever the fault.
TEST_F(BadInput, UpdateTimeStepReportsFailure)
{
  {
    Rig rig(ThreeQuads());
    rig.Filter->SetWeight(1, 0.5);
    EXPECT_EQ(rig.Filter->UpdateTimeStep(0.0), 1);
    EXPECT_EQ(rig.Filter->GetOutput()->GetNumberOfPoints(), 4);
    rig.Filter->SetWeight(1, std::numeric_limits<double>::quiet_NaN());
    EXPECT_EQ(rig.Filter->UpdateTimeStep(0.0), 0);
    EXPECT_EQ(rig.Filter->GetOutput()->GetNumberOfPoints(), 0);
    EXPECT_TRUE(rig.Messages->HasError("weight 1 is nan")) << rig.Messages->AllErrors();
    EXPECT_EQ(rig.Filter->GetEffectiveWeight(0), 0.0);
  }
  {
    Rig rig(ThreeQuads());
    rig.Filter->SetWeightByName("jawOpen", 0.5);
    EXPECT_EQ(rig.Filter->UpdateTimeStep(0.0), 0);
    EXPECT_EQ(rig.Filter->GetOutput()->GetNumberOfPoints(), 0);
    EXPECT_TRUE(rig.Messages->HasError("no target has that name")) << rig.Messages->AllErrors();
  }
  {
    auto targets = ThreeQuads();
    targets[2]->GetPoints()->InsertNextPoint(5, 5, 5);
    Rig rig(targets);
    EXPECT_EQ(rig.Filter->UpdateTimeStep(0.0), 0);
    EXPECT_EQ(rig.Filter->GetOutput()->GetNumberOfPoints(), 0);
    EXPECT_EQ(rig.Filter->GetNumberOfTargets(), 3); // the connections; nothing was built
    EXPECT_TRUE(rig.Messages->HasError("target 2 has 5 points")) << rig.Messages->AllErrors();
  }
}

TEST_F(BadInput, RecoversOnceTheInputIsFixed)
{
  Rig rig(ThreeQuads());
  rig.Filter->SetWeight(1, std::numeric_limits<double>::quiet_NaN());
  rig.Run();
  rig.Filter->SetWeight(1, 0.5);
  EXPECT_EQ(rig.Run()->GetNumberOfPoints(), 4);
}

TEST(MorphNodeFilter, NoInputIsAnErrorNotACrash)
{
  vtkNew<vtkMorphNodeFilter> filter;
  vtkNew<MessageCollector> messages;
  messages->Watch(filter);
  messages->Watch(filter->GetExecutive());
  filter->Update();
  EXPECT_FALSE(messages->Errors.empty());
  EXPECT_EQ(filter->GetNumberOfTargets(), 0);
}

TEST(MorphNodeFilter, HonoursPieceRequests)
{
  // Two spheres that split into the same pieces; the morph of piece 0 of 2 is piece 0 of
  // 2 of the morph.
  vtkNew<vtkSphereSource> neutral, big;
  big->SetRadius(2.0);
  for (auto* s : { neutral.Get(), big.Get() })
  {
    s->SetThetaResolution(32);
    s->SetPhiResolution(16);
  }
  vtkNew<vtkMorphNodeFilter> morph;
  morph->AddInputConnection(0, neutral->GetOutputPort());
  morph->AddInputConnection(0, big->GetOutputPort());
  morph->SetWeight(1, 1.0); // normalized: half way between radius 0.5 and 2
  morph->UpdatePiece(0, 2, 0);
  auto* piece = vtkPolyData::SafeDownCast(morph->GetOutput());
  vtkNew<vtkSphereSource> whole;
  whole->SetThetaResolution(32);
  whole->SetPhiResolution(16);
  whole->Update();
  ASSERT_GT(piece->GetNumberOfPoints(), 0);
  EXPECT_LT(piece->GetNumberOfPoints(), whole->GetOutput()->GetNumberOfPoints());
  for (vtkIdType i = 0; i < piece->GetNumberOfPoints(); ++i)
  {
    EXPECT_NEAR(vtkMath::Norm(piece->GetPoint(i)), 1.25, 1e-5);
  }
}

TEST(MorphNodeFilter, ReportsProgress)
{
  Rig rig(ThreeQuads());
  std::vector<double> progress;
  vtkNew<vtkCallbackCommand> observer;
  observer->SetClientData(&progress);
  observer->SetCallback([](vtkObject*, unsigned long, void* client, void* data)
    { static_cast<std::vector<double>*>(client)->push_back(*static_cast<double*>(data)); });
  rig.Filter->AddObserver(vtkCommand::ProgressEvent, observer);
  rig.Filter->SetWeight(1, 0.5);
  rig.Run();
  ASSERT_GE(progress.size(), 3u);
  EXPECT_EQ(progress.front(), 0.0);
  EXPECT_EQ(progress.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
}

TEST(MorphNodeFilter, PrintSelfShowsSettings)
{
  vtkNew<vtkMorphNodeFilter> filter;
  filter->SetThreshold(0.2);
  filter->SetWeightByName("A", 0.3);
  std::ostringstream os;
  filter->Print(os);
  EXPECT_NE(os.str().find("Threshold: 0.2"), std::string::npos);
  EXPECT_NE(os.str().find("A=0.3"), std::string::npos);
  EXPECT_NE(os.str().find("WeightMode: Normalize"), std::string::npos);
}
