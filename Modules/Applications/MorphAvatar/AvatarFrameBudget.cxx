// SPDX-License-Identifier: BSD-3-Clause
#include "AvatarFrameBudget.h"

#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkMorphNodeFilter.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkSmartPointer.h"

#include "base/File.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <vector>

namespace morphavatar
{
namespace
{
/// Records the filter's choice after every successful execution; writes the summary when
/// the filter (and so this observer) goes away at the avatar's end.
class FrameBudgetWatch : public vtkCommand
{
public:
  static FrameBudgetWatch* New();
  vtkTypeMacro(FrameBudgetWatch, vtkCommand);

  double Budget = 0.0; // ms
  bool Quiet = false;
  std::unique_ptr<morphnode::file::SafeOutput> Log; // written beside, renamed when complete
  std::string LogError;

  void Execute(vtkObject* caller, unsigned long, void*) override
  {
    auto* morph = vtkMorphNodeFilter::SafeDownCast(caller);
    if (!morph || morph->GetFrameBudgetThreshold() < 0.0)
    {
      return; // no budget in this execution (or it failed)
    }
    const double threshold = morph->GetFrameBudgetThreshold();
    const double ms = morph->GetMorphTime();
    const int active = morph->GetActiveTargetCount();
    // The mesh level shown (0 without MeshLevels) and the points of the morph's output.
    const int level = std::max(0, morph->GetLevel());
    vtkDataObject* output = morph->GetOutputDataObject(0);
    const vtkIdType points = output ? output->GetNumberOfElements(vtkDataObject::POINT) : 0;
    if (this->Log)
    {
      std::ostringstream line;
      line << this->Thresholds.size() << "," << threshold << "," << active << ","
           << std::setprecision(6) << ms << "," << this->Budget << "," << level << "," << points
           << "\n";
      this->WriteLog(line.str());
    }
    this->Levels[level] += 1;
    this->Thresholds.push_back(threshold);
    this->Times.push_back(ms);
    this->Active.push_back(active);
  }

  void WriteLog(const std::string& text)
  {
    try
    {
      this->Log->Write(text);
    }
    catch (const std::exception& e) // a full disk: no partial log, a message, exit 1
    {
      this->LogError = e.what();
      this->Log.reset();
    }
  }

  /// Completes the log (checked close and rename); false with the message when it failed.
  bool FinishLog()
  {
    if (this->Log)
    {
      try
      {
        this->Log->Commit();
      }
      catch (const std::exception& e)
      {
        this->LogError = e.what();
      }
      this->Log.reset();
    }
    if (!this->LogError.empty())
    {
      std::cerr << "MorphAvatar: --frame-budget-log: " << this->LogError << "\n";
      this->LogError.clear();
      return false;
    }
    return true;
  }

protected:
  FrameBudgetWatch() = default;
  ~FrameBudgetWatch() override
  {
    if (this->Quiet || this->Times.empty())
    {
      return;
    }
    // The first frame was decided before anything was measured: not counted.
    const size_t first = this->Times.size() > 1 ? 1 : 0;
    const size_t n = this->Times.size() - first;
    size_t within = 0, changes = 0;
    double thresholdSum = 0.0, activeSum = 0.0;
    for (size_t i = first; i < this->Times.size(); ++i)
    {
      within += this->Times[i] <= this->Budget ? 1 : 0;
      changes += i > first && this->Thresholds[i] != this->Thresholds[i - 1] ? 1 : 0;
      thresholdSum += this->Thresholds[i];
      activeSum += this->Active[i];
    }
    std::vector<double> sorted(
      this->Times.begin() + static_cast<std::ptrdiff_t>(first), this->Times.end());
    std::sort(sorted.begin(), sorted.end());
    std::cout << "frame budget " << this->Budget << " ms: " << std::fixed << std::setprecision(3)
              << n << " frames, within budget " << std::setprecision(1)
              << 100.0 * double(within) / double(n) << " %, morph time median "
              << std::setprecision(3) << sorted[sorted.size() / 2] << " ms, 95th percentile "
              << sorted[std::min(sorted.size() - 1, sorted.size() * 95 / 100)]
              << " ms; threshold changed on " << changes << " frames, mean threshold "
              << thresholdSum / double(n) << ", mean active targets " << std::setprecision(2)
              << activeSum / double(n) << "\n";
    if (this->Levels.size() > 1 || this->Levels.count(0) == 0)
    {
      std::cout << "mesh levels shown:";
      for (const auto& [level, frames] : this->Levels)
      {
        std::cout << " level " << level << " " << frames << " frames";
      }
      std::cout << "\n";
    }
  }

private:
  std::vector<double> Thresholds, Times;
  std::vector<int> Active;
  std::map<int, size_t> Levels; // mesh level -> frames shown
};
vtkStandardNewMacro(FrameBudgetWatch);

vtkSmartPointer<FrameBudgetWatch> ActiveWatch; // the one watch of the program, for its log
} // namespace

void WatchFrameBudget(vtkMorphNodeFilter* morph, const Options& o)
{
  // --frame-budget, else a --profile's budget (already set on the filter).
  if (o.FrameBudget > 0.0)
  {
    morph->SetFrameBudget(o.FrameBudget);
  }
  const double budget = morph->GetFrameBudget();
  if (!(budget > 0.0))
  {
    return;
  }
  vtkNew<FrameBudgetWatch> watch;
  watch->Budget = budget;
  watch->Quiet = o.Quiet;
  if (!o.FrameBudgetLog.empty())
  {
    try
    {
      watch->Log =
        std::make_unique<morphnode::file::SafeOutput>(o.FrameBudgetLog, "--frame-budget-log");
    }
    catch (const std::exception& e)
    {
      FailUsage(e.what());
    }
    watch->WriteLog("frame,threshold,active_targets,morph_ms,budget_ms,level,points\n");
  }
  morph->AddObserver(vtkCommand::EndEvent, watch);
  ActiveWatch = watch;
}

bool FinishFrameBudget()
{
  const bool ok = !ActiveWatch || ActiveWatch->FinishLog();
  ActiveWatch = nullptr;
  return ok;
}
} // namespace morphavatar
