// SPDX-License-Identifier: BSD-3-Clause
#include "HeadPoseTransform.h"

#include "vtkDataArray.h"
#include "vtkTable.h"
#include "vtkTransform.h"

namespace morphnode
{
namespace appkit
{
namespace
{
double Channel(vtkTable* table, const char* name)
{
  auto* data = table ? vtkArrayDownCast<vtkDataArray>(table->GetColumnByName(name)) : nullptr;
  return data && data->GetNumberOfTuples() > 0 ? data->GetTuple1(0) : 0.0;
}
} // namespace

HeadAngles ReadHeadAngles(vtkTable* weights)
{
  HeadAngles a;
  a.Yaw = Channel(weights, "HeadYaw");
  a.Pitch = Channel(weights, "HeadPitch");
  a.Roll = Channel(weights, "HeadRoll");
  return a;
}

void SetHeadPose(vtkTransform* transform, const HeadAngles& angles, const std::array<double, 3>& pivot)
{
  transform->SetMatrix(HeadPoseMatrix(FiniteHeadAngles(angles), pivot).data());
}
} // namespace appkit
} // namespace morphnode
