// SPDX-License-Identifier: BSD-3-Clause
// The morph-stage benchmark suite: every figure is a ratio of two timings taken in the
// same run, on the same face and weights.
//
//   BenchMorph [--smoke] [--markdown FILE] [--face FILE.glb]
//
// Baselines: a naive Java3D-style blend (absolute shapes, every target, no skipping);
// VTK 9.1's glTF morphing loop (vtkGLTFReader's ApplyMorphingToDataArray, replicated:
// dense, virtual GetTuple per component); a plain hand-written skip-zero loop over flat
// float arrays; the machine's memory bandwidth (STREAM-like triad, measured here); and
// the raw kernel under the whole VTK pipeline. --smoke runs every case once, briefly,
// for CI: it checks that the suite runs, and asserts nothing about time.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "morph/MorphAttribute.h"
#include "morph/MorphMesh.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointSetAlgorithm.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using morphnode::AttributeRole;
using morphnode::MorphAttribute;

namespace
{
bool Smoke = false;
volatile float Sink = 0.0f; // keeps results alive

/// Seconds per call: every call timed on its own for about `budget` seconds (at least 5
/// calls), the 10th percentile reported. On a machine shared with other jobs a preempted
/// or cache-flushed call only moves the upper tail, so ratios of two such figures stay
/// stable where means over batches do not.
double TimePerCall(const std::function<void()>& work, double budget = 0.6)
{
  if (Smoke)
  {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  // Let the vtkSMPTools workers of an earlier timing fall asleep: while they spin (TBB
  // workers do so for a while after a parallel loop) a one-thread timing ran up to 1.8x
  // slower on this 2-vCPU machine.
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  work(); // warm up caches and pages
  std::vector<double> times;
  times.reserve(1 << 16);
  const auto start = std::chrono::steady_clock::now();
  double total = 0.0;
  do
  {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    const auto t1 = std::chrono::steady_clock::now();
    times.push_back(std::chrono::duration<double>(t1 - t0).count());
    total = std::chrono::duration<double>(t1 - start).count();
  } while ((total < budget || times.size() < 5) && times.size() < (1u << 20));
  const size_t k = times.size() / 10;
  std::nth_element(times.begin(), times.begin() + static_cast<std::ptrdiff_t>(k), times.end());
  return times[k];
}

/// Seconds per call of several works, timed in short alternated rounds. This machine's
/// speed drifts by tens of percent over seconds (a shared VM), so a ratio is taken within
/// each round, where both sides saw the same machine, and the median over rounds reported.
struct Alternated
{
  std::vector<std::vector<double>> Rounds; // Rounds[r][k]: work k in round r

  /// `beforeRound` runs before each round, untimed.
  Alternated(const std::vector<std::function<void()>>& works, double budget, int rounds = 10,
    const std::function<void()>& beforeRound = {})
  {
    for (int round = 0; round < (Smoke ? 1 : rounds); ++round)
    {
      if (beforeRound)
      {
        beforeRound();
      }
      std::vector<double> times;
      for (const auto& work : works)
      {
        times.push_back(TimePerCall(work, budget));
      }
      this->Rounds.push_back(times);
    }
  }
  /// Median over rounds of work k's time.
  double Time(size_t k) const
  {
    return this->Median([k](const std::vector<double>& t) { return t[k]; });
  }
  /// Median over rounds of time(num) / time(den).
  double Ratio(size_t num, size_t den) const
  {
    return this->Median([num, den](const std::vector<double>& t) { return t[num] / t[den]; });
  }

private:
  template <typename F>
  double Median(F value) const
  {
    std::vector<double> v;
    for (const auto& round : this->Rounds)
    {
      v.push_back(value(round));
    }
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  }
};

// The yardsticks are built for AVX2 and the baseline like the core's dense kernels
// (MorphAttribute.cpp), so every side of a ratio gets the same instructions.
#if defined(__x86_64__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define MORPHNODE_BENCH_CLONES __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef MORPHNODE_BENCH_CLONES
#define MORPHNODE_BENCH_CLONES
#endif

/// About the cheapest filter VTK can run: it hands on the input's points and cells, no
/// arrays. Its Update is the executive's own cost per time step, the floor under any
/// filter's (vtkMorphNodeFilter's included).
class PassPoints : public vtkPointSetAlgorithm
{
public:
  static PassPoints* New();
  vtkTypeMacro(PassPoints, vtkPointSetAlgorithm);

protected:
  int RequestData(vtkInformation*, vtkInformationVector** in, vtkInformationVector* out) override
  {
    vtkPointSet::GetData(out)->CopyStructure(vtkPointSet::GetData(in[0]));
    return 1;
  }
};
vtkStandardNewMacro(PassPoints);

/// A face as flat float arrays: neutral and dense deltas of every target.
struct Face
{
  size_t NumPoints = 0;
  std::vector<float> Neutral;
  std::vector<std::vector<float>> Deltas;
  std::vector<std::string> Names;
};

Face LoadFace(const std::string& file)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetNormalsMode(vtkMorphTargetReader::NORMALS_FROM_FILE); // positions only
  reader->Update();
  vtkPolyData* pd = reader->GetOutput();
  Face face;
  face.NumPoints = static_cast<size_t>(pd->GetNumberOfPoints());
  auto flat = [](vtkDataArray* a) {
    std::vector<float> v(static_cast<size_t>(a->GetNumberOfValues()));
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        v[static_cast<size_t>(3 * i + c)] = static_cast<float>(a->GetComponent(i, c));
      }
    }
    return v;
  };
  if (face.NumPoints == 0)
  {
    return face;
  }
  face.Neutral = flat(pd->GetPoints()->GetData());
  for (int k = 0; k + 1 < reader->GetNumberOfTargets(); ++k)
  {
    face.Deltas.push_back(flat(pd->GetPointData()->GetArray(("target" + std::to_string(k) + "_position").c_str())));
    face.Names.push_back(reader->GetTargetName(k + 1));
  }
  return face;
}

/// A synthetic face when no file is available: 11,248 points, 53 targets, each moving a
/// contiguous region like a real action unit.
Face SyntheticFace()
{
  Face face;
  face.NumPoints = 11248;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  face.Neutral.resize(face.NumPoints * 3);
  for (auto& v : face.Neutral)
  {
    v = u(rng);
  }
  for (int k = 0; k < 53; ++k)
  {
    std::vector<float> d(face.NumPoints * 3, 0.f);
    const size_t start = (k * 997) % face.NumPoints, span = face.NumPoints / 2;
    for (size_t p = 0; p < span; ++p)
    {
      for (int c = 0; c < 3; ++c)
      {
        d[((start + p) % face.NumPoints) * 3 + c] = 0.01f * u(rng);
      }
    }
    face.Deltas.push_back(std::move(d));
    face.Names.push_back("target" + std::to_string(k));
  }
  return face;
}

MorphAttribute<float> BuildAttribute(const Face& face, double sparseCoverage)
{
  MorphAttribute<float> a("Points", AttributeRole::Position, 3, face.NumPoints);
  a.SetNeutral(face.Neutral.data());
  for (const auto& d : face.Deltas)
  {
    a.AddRelativeTarget(d.data(), sparseCoverage);
  }
  return a;
}

/// Absolute weights (neutral first) with `active` non-zero targets spread over the face.
std::vector<double> Weights(size_t numTargets, const std::vector<size_t>& active)
{
  std::vector<double> w(numTargets + 1, 0.0);
  double sum = 0.0;
  for (size_t k = 0; k < active.size(); ++k)
  {
    w[active[k] + 1] = 0.05 + 0.5 * static_cast<double>((k * 37) % 10) / 10.0;
    sum += w[active[k] + 1];
  }
  w[0] = std::max(0.0, 1.0 - sum);
  return w;
}

std::vector<size_t> SpeechTargets(const Face& face)
{
  // ICT/ARKit names of a speech frame; fall back to evenly spread indices.
  const char* speech[] = { "jawOpen", "mouthFunnel", "mouthPucker", "mouthClose", "mouthSmile_L",
    "mouthSmile_R", "mouthLowerDown_L", "mouthLowerDown_R" };
  std::vector<size_t> ids;
  for (const char* name : speech)
  {
    auto it = std::find(face.Names.begin(), face.Names.end(), name);
    if (it != face.Names.end())
    {
      ids.push_back(static_cast<size_t>(it - face.Names.begin()));
    }
  }
  for (size_t k = 0; ids.size() < 8 && k < face.Deltas.size(); k += 7)
  {
    ids.push_back(k);
  }
  return ids;
}

std::vector<size_t> AllTargets(const Face& face)
{
  std::vector<size_t> ids(face.Deltas.size());
  for (size_t k = 0; k < ids.size(); ++k)
  {
    ids[k] = k;
  }
  return ids;
}

// --- the yardsticks ---------------------------------------------------------------

/// Plain skip-zero loop over flat float arrays, one thread: what anyone would write.
MORPHNODE_BENCH_CLONES void PlainSkipZero(const Face& face, const std::vector<double>& w, std::vector<float>& out)
{
  std::copy(face.Neutral.begin(), face.Neutral.end(), out.begin());
  for (size_t k = 0; k < face.Deltas.size(); ++k)
  {
    const float wk = static_cast<float>(w[k + 1]);
    if (wk == 0.f)
    {
      continue;
    }
    const float* d = face.Deltas[k].data();
    float* o = out.data();
    const size_t n = out.size();
    for (size_t i = 0; i < n; ++i)
    {
      o[i] += wk * d[i];
    }
  }
}

/// Java3D-style: absolute shapes, every target, no skipping.
void NaiveJava3D(const std::vector<std::vector<float>>& shapes, const std::vector<double>& w,
  std::vector<float>& out)
{
  std::fill(out.begin(), out.end(), 0.f);
  for (size_t k = 0; k < shapes.size(); ++k)
  {
    const float wk = static_cast<float>(w[k]);
    const float* s = shapes[k].data();
    for (size_t i = 0; i < out.size(); ++i)
    {
      out[i] += wk * s[i];
    }
  }
}

/// VTK 9.1 vtkGLTFReader's ApplyMorphingToDataArray (what ApplyDeformationsToGeometry runs
/// per primitive and attribute), replicated statement for statement: a new result array
/// deep-copied from the origin, then per tuple, per target, per component a virtual
/// GetTuple call; dense; nothing skipped. Returns the new array like VTK does.
vtkSmartPointer<vtkDataArray> VTKGLTFLoop(vtkDataArray* origin, const std::vector<float>& weights,
  const std::vector<vtkSmartPointer<vtkFloatArray>>& targets)
{
  vtkSmartPointer<vtkDataArray> result = vtkSmartPointer<vtkDataArray>::Take(origin->NewInstance());
  result->DeepCopy(origin);
  std::vector<double> tuple(static_cast<size_t>(origin->GetNumberOfComponents()), 0);
  for (vtkIdType t = 0; t < origin->GetNumberOfTuples(); ++t)
  {
    origin->GetTuple(t, tuple.data());
    for (size_t k = 0; k < targets.size(); ++k)
    {
      for (int c = 0; c < targets[k]->GetNumberOfComponents(); ++c)
      {
        tuple[static_cast<size_t>(c)] += weights[k] * targets[k]->GetTuple(t)[c];
      }
    }
    result->SetTuple(t, tuple.data());
  }
  return result;
}

/// STREAM triad a = b + s c over three arrays of `bytesPerArray`: one thread, or on the
/// vtkSMPTools pool the kernel runs on (two pools would compete for the cores).
MORPHNODE_BENCH_CLONES void TriadRange(
  float* __restrict a, const float* __restrict b, const float* __restrict c, size_t lo, size_t hi)
{
  for (size_t i = lo; i < hi; ++i)
  {
    a[i] = b[i] + 3.f * c[i];
  }
}

struct Triad
{
  explicit Triad(size_t bytesPerArray)
    : N(std::max<size_t>(bytesPerArray / sizeof(float), 1024))
  {
  }
  size_t N;
  std::vector<float> A = std::vector<float>(N, 0.f), B = std::vector<float>(N, 1.f),
                     C = std::vector<float>(N, 2.f);

  void Run(int threads)
  {
    auto range = [this](size_t lo, size_t hi) { TriadRange(A.data(), B.data(), C.data(), lo, hi); };
    if (threads == 1)
    {
      range(0, N);
    }
    else
    {
      vtkSMPTools::For(0, static_cast<vtkIdType>(N), static_cast<vtkIdType>(N / 64),
        [&](vtkIdType lo, vtkIdType hi) { range(static_cast<size_t>(lo), static_cast<size_t>(hi)); });
    }
    Sink = A[N / 2];
  }
  /// Bytes per second from the seconds one Run took (STREAM's count: 3 arrays).
  double Bandwidth(double seconds) const { return 3.0 * N * sizeof(float) / seconds; }
};

/// Blends with the core kernel: one thread, or vtkSMPTools over points with the grain the
/// VTK module uses (vtkMorphModelAdapter::Blend), on the pool of both cores.
void KernelBlend(const MorphAttribute<float>& a, const std::vector<double>& w, std::vector<float>& out, int threads)
{
  if (threads == 1)
  {
    a.Blend(w.data(), w.size(), out.data(), 0, a.GetNumberOfPoints());
    return;
  }
  vtkSMPTools::For(0, static_cast<vtkIdType>(a.GetNumberOfPoints()), 1024, [&](vtkIdType begin, vtkIdType end) {
    a.Blend(w.data(), w.size(), out.data(), static_cast<size_t>(begin), static_cast<size_t>(end));
  });
}

std::string Format(double value)
{
  std::ostringstream v;
  v << std::setprecision(3) << value;
  return v.str();
}

/// First line of `file` starting with `key`, the rest after the colon, trimmed.
std::string ReadField(const std::string& file, const std::string& key)
{
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
  {
    if (line.rfind(key, 0) == 0)
    {
      const size_t colon = line.find(':');
      std::string v = colon == std::string::npos ? line : line.substr(colon + 1);
      v.erase(0, v.find_first_not_of(" \t"));
      return v;
    }
  }
  return "?";
}

std::string LoadAverage()
{
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " / " + five + " / " + fifteen;
}

struct Report
{
  std::ostringstream Text;
  std::ostringstream Goals;
  /// A goal: measured value against a bound, pass or miss.
  void Goal(const std::string& what, double value, const std::string& unit, const std::string& bound, bool pass)
  {
    this->Goals << "| " << what << " | " << Format(value) << " " << unit << " | " << bound << " | "
                << (pass ? "**pass**" : "**MISS**") << " |\n";
  }
  void Row(const std::string& what, double value, const std::string& unit, const std::string& goal = "")
  {
    std::ostringstream v;
    v << std::setprecision(3) << value;
    this->Text << "| " << what << " | " << v.str() << " " << unit << " | " << goal << " |\n";
    std::cout << std::left << std::setw(78) << what << std::setw(12) << v.str() << unit
              << (goal.empty() ? "" : "   (goal: " + goal + ")") << "\n";
  }
};
} // namespace

int main(int argc, char* argv[])
{
  std::string face = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  std::string markdown;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--smoke")
    {
      Smoke = true;
    }
    else if (arg == "--markdown" && i + 1 < argc)
    {
      markdown = argv[++i];
    }
    else if (arg == "--face" && i + 1 < argc)
    {
      face = argv[++i];
    }
    else
    {
      std::cerr << "usage: BenchMorph [--smoke] [--markdown FILE] [--face FILE.glb]\n";
      return 2;
    }
  }
  Face ict = std::ifstream(face) ? LoadFace(face) : Face();
  std::string faceName = face;
  if (ict.NumPoints == 0)
  {
    ict = SyntheticFace();
    faceName = "synthetic face (11,248 points, 53 targets; ICT-FaceKit not found)";
  }
  vtkSMPTools::Initialize(2);
  Report report;
  const std::string loadBefore = LoadAverage();
  std::cout << "Face: " << faceName << " (" << ict.NumPoints << " points, " << ict.Deltas.size()
            << " targets)\n";

  const MorphAttribute<float> kernel = BuildAttribute(ict, morphnode::MorphMesh::DefaultSparseCoverage);
  std::vector<float> out(ict.NumPoints * 3), ref(ict.NumPoints * 3);

  // Absolute shapes for the Java3D baseline; VTK arrays for VTK's loop.
  std::vector<std::vector<float>> shapes{ ict.Neutral };
  vtkNew<vtkFloatArray> origin;
  vtkSmartPointer<vtkDataArray> result;
  origin->SetNumberOfComponents(3);
  origin->SetNumberOfTuples(static_cast<vtkIdType>(ict.NumPoints));
  std::copy(ict.Neutral.begin(), ict.Neutral.end(), origin->GetPointer(0));
  std::vector<vtkSmartPointer<vtkFloatArray>> vtkTargets;
  for (const auto& d : ict.Deltas)
  {
    std::vector<float> s(ict.Neutral);
    for (size_t i = 0; i < s.size(); ++i)
    {
      s[i] += d[i];
    }
    shapes.push_back(std::move(s));
    auto t = vtkSmartPointer<vtkFloatArray>::New();
    t->SetNumberOfComponents(3);
    t->SetNumberOfTuples(static_cast<vtkIdType>(ict.NumPoints));
    std::copy(d.begin(), d.end(), t->GetPointer(0));
    vtkTargets.push_back(t);
  }

  // The VTK pipeline over the same face, glTF form.
  vtkNew<vtkPolyData> input;
  vtkNew<vtkPoints> points;
  points->SetData(origin);
  input->SetPoints(points);
  for (size_t k = 0; k < vtkTargets.size(); ++k)
  {
    vtkTargets[k]->SetName(("target" + std::to_string(k) + "_position").c_str());
    input->GetPointData()->AddArray(vtkTargets[k]);
  }
  vtkNew<vtkMorphNodeFilter> filter;
  filter->SetInputData(input);
  filter->SetWeightModeToRelative();
  filter->Update();
  vtkNew<PassPoints> passThrough;
  passThrough->SetInputData(input);

  for (const auto& [caseName, active] :
    { std::make_pair(std::string("speech frame"), SpeechTargets(ict)),
      std::make_pair(std::string("all targets"), AllTargets(ict)) })
  {
    const std::vector<double> w = Weights(ict.Deltas.size(), active);
    std::vector<float> wf(w.begin() + 1, w.end());
    const std::string tag = caseName + " (" + std::to_string(active.size()) + " of " +
      std::to_string(ict.Deltas.size()) + " active)";
    const double ours1 = TimePerCall([&] { KernelBlend(kernel, w, out, 1); });
    const double plain = TimePerCall([&] { PlainSkipZero(ict, w, ref); });
    const double naive = TimePerCall([&] { NaiveJava3D(shapes, w, ref); });
    const double vtk = TimePerCall([&] { result = VTKGLTFLoop(origin, wf, vtkTargets); }, Smoke ? 0 : 1.0);
    // Pipeline: a weight change and an Update per step, as a time source would drive it;
    // timed in rounds alternated with the raw kernel it is compared with.
    int step = 0;
    for (size_t k = 0; k < active.size(); ++k)
    {
      filter->SetWeight(static_cast<int>(active[k] + 1), w[active[k] + 1]);
    }
    const Alternated alternated(
      { [&] { KernelBlend(kernel, w, out, 2); },
        [&] {
          filter->SetWeight(static_cast<int>(active[0] + 1), w[active[0] + 1] + 1e-6 * (++step % 2));
          filter->Update();
        },
        [&] {
          passThrough->Modified();
          passThrough->Update();
        } },
      0.08);
    const double oursSmp = alternated.Time(0), pipeline = alternated.Time(1);
    const double floor = alternated.Time(2);
    const double pipelineRatio = alternated.Ratio(1, 0);
    for (size_t k = 0; k < ict.Deltas.size(); ++k)
    {
      filter->SetWeight(static_cast<int>(k + 1), 0.0);
    }
    Sink = out[0] + ref[0];
    if (caseName == "speech frame")
    {
      report.Goal("ICT speech frame: VTK 9.1 glTF morphing loop / core kernel (1 thread)", vtk / ours1, "x", ">= 150 x", vtk / ours1 >= 150);
      report.Goal("ICT speech frame: core kernel / plain skip-zero loop (1 thread)", ours1 / plain, "x", "<= 1.3 x", ours1 / plain <= 1.3);
    }
    // The issue's goal, in its words: "the VTK pipeline adds at most 2 times the raw kernel
    // time", i.e. Update - kernel <= 2 kernel. The whole Update against the kernel is reported
    // beside it (a row, not a goal): VTK's executive alone costs about 0.6 kernels here.
    report.Goal("ICT " + caseName + ": time the VTK pipeline adds / raw kernel (both vtkSMPTools, 2 threads)", pipelineRatio - 1.0, "x", "<= 2 x", pipelineRatio - 1.0 <= 2.0);
    report.Text << "\n**ICT face, " << tag << "**\n\n| measure | value | goal |\n| --- | --- | --- |\n";
    std::cout << "\n" << tag << "\n";
    report.Row("core kernel, 1 thread: time per frame", ours1 * 1e6, "us");
    report.Row("core kernel, vtkSMPTools (2 threads): time per frame", oursSmp * 1e6, "us");
    report.Row("plain skip-zero loop, 1 thread: time per frame", plain * 1e6, "us");
    report.Row("VTK 9.1 glTF morphing loop: time per frame", vtk * 1e6, "us");
    report.Row("vtkMorphNodeFilter Update: time per step", pipeline * 1e6, "us");
    report.Row("VTK's floor: Update of a filter that passes the points on", floor * 1e6, "us");
    report.Row("vtkMorphNodeFilter's own per-step work (Update - kernel - floor)",
      (pipeline - oursSmp - floor) * 1e6, "us");
    report.Row("VTK 9.1 glTF morphing loop / core kernel (1 thread)", vtk / ours1, "x",
      caseName == "speech frame" ? ">= 150 x" : "");
    report.Row("naive Java3D blend / core kernel (1 thread)", naive / ours1, "x");
    report.Row("core kernel / plain skip-zero loop (1 thread)", ours1 / plain, "x",
      caseName == "speech frame" ? "<= 1.3 x" : "");
    report.Row("time the VTK pipeline adds / core kernel (both vtkSMPTools, 2 threads)", pipelineRatio - 1.0, "x", "<= 2 x");
    report.Row("vtkMorphNodeFilter Update / core kernel (both vtkSMPTools, 2 threads)", pipelineRatio, "x");
    report.Row("vtkMorphNodeFilter Update / core kernel (1 thread)", pipeline / ours1, "x");
  }

  // Doubling the number of inactive targets.
  {
    Face doubled = ict;
    for (size_t k = 0; k < ict.Deltas.size(); ++k)
    {
      doubled.Deltas.push_back(ict.Deltas[k]);
      doubled.Names.push_back(ict.Names[k] + "_copy");
    }
    const MorphAttribute<float> big = BuildAttribute(doubled, morphnode::MorphMesh::DefaultSparseCoverage);
    const std::vector<size_t> active = SpeechTargets(ict);
    const std::vector<double> w1 = Weights(ict.Deltas.size(), active);
    const std::vector<double> w2 = Weights(doubled.Deltas.size(), active);
    const Alternated t(
      { [&] { KernelBlend(kernel, w1, out, 1); }, [&] { KernelBlend(big, w2, out, 1); } }, 0.08, 12);
    const double t1 = t.Time(0), t2 = t.Time(1);
    const double change = std::abs(t.Ratio(1, 0) - 1.0);
    report.Goal("ICT speech frame: time change from doubling the inactive targets (53 -> 106)", change * 100, "%", "< 5 %", change < 0.05);
    report.Text << "\n**Inactive targets cost nothing**\n\n| measure | value | goal |\n| --- | --- | --- |\n";
    std::cout << "\nInactive targets\n";
    report.Row("speech frame, 53 targets: time per frame", t1 * 1e6, "us");
    report.Row("speech frame, 106 targets: time per frame", t2 * 1e6, "us");
    report.Row("speech frame, 106 targets / 53 targets (same " + std::to_string(active.size()) + " active)", t.Ratio(1, 0), "x", "within 5 %");
  }

  // Scaling with the number of active targets.
  {
    report.Text << "\n**Scaling with active targets (ICT face, 1 thread)**\n\n| active targets | time per frame | |\n| --- | --- | --- |\n";
    std::cout << "\nScaling with active targets\n";
    for (size_t count : { 1, 2, 4, 8, 16, 32, 53 })
    {
      std::vector<size_t> active;
      for (size_t k = 0; k < count && k < ict.Deltas.size(); ++k)
      {
        active.push_back((k * 13) % ict.Deltas.size());
      }
      const std::vector<double> w = Weights(ict.Deltas.size(), active);
      report.Row(std::to_string(active.size()), TimePerCall([&] { KernelBlend(kernel, w, out, 1); }, 0.3) * 1e6, "us");
    }
  }

  // Sparse against dense storage for one target moving a fraction of 100k points: the
  // moved points scattered at random (the worst case for spans), and in runs of 24 points
  // on average, as on the ICT face (its 30-50 % targets; the default face's runs average 34).
  {
    report.Text << "\n**Sparse or dense deltas: one target, 100k points, 1 thread**\n\n"
                << "| moved points | scattered: sparse | in runs: sparse | dense | scattered: sparse / dense | in runs: sparse / dense |\n"
                << "| --- | --- | --- | --- | --- | --- |\n";
    std::cout << "\nSparse / dense crossover (scattered, in runs)\n";
    const size_t n = 100000;
    std::vector<float> neutral(n * 3, 0.f), o(n * 3);
    std::mt19937 rng(3);
    const double meanRun = 24.0;
    const auto scattered = [&](double fraction) {
      std::vector<float> delta(n * 3, 0.f);
      std::bernoulli_distribution moved(fraction);
      for (size_t p = 0; p < n; ++p)
      {
        if (moved(rng))
        {
          delta[3 * p] = delta[3 * p + 1] = delta[3 * p + 2] = 0.001f;
        }
      }
      return delta;
    };
    const auto inRuns = [&](double fraction) {
      std::vector<float> delta(n * 3, 0.f);
      if (fraction >= 1.0)
      {
        std::fill(delta.begin(), delta.end(), 0.001f);
        return delta;
      }
      // Runs and gaps of geometric length: mean run 24, mean gap 24 (1 - f) / f.
      std::geometric_distribution<size_t> run(1.0 / meanRun), gap(fraction / (fraction + meanRun * (1.0 - fraction)));
      for (size_t p = gap(rng); p < n; p += gap(rng) + 1)
      {
        for (const size_t end = std::min(n, p + run(rng) + 1); p < end; ++p)
        {
          delta[3 * p] = delta[3 * p + 1] = delta[3 * p + 2] = 0.001f;
        }
      }
      return delta;
    };
    const double w[2] = { 0.5, 0.5 };
    const auto timeBlend = [&](const std::vector<float>& delta, double coverage) {
      MorphAttribute<float> a("P", AttributeRole::Position, 3, n);
      a.SetNeutral(neutral.data());
      a.AddRelativeTarget(delta.data(), coverage);
      return TimePerCall([&] { a.Blend(w, 2, o.data(), 0, n); }, 0.2);
    };
    // The last crossing from sparse-faster to dense-faster (noise may cross earlier too).
    struct Crossing
    {
      double PreviousFraction = 0.0, PreviousRatio = 0.0, At = -1.0;
      void Add(double fraction, double ratio)
      {
        if (this->PreviousRatio > 0 && this->PreviousRatio < 1.0 && ratio >= 1.0)
        {
          this->At = this->PreviousFraction +
            (1.0 - this->PreviousRatio) * (fraction - this->PreviousFraction) / (ratio - this->PreviousRatio);
        }
        this->PreviousFraction = fraction;
        this->PreviousRatio = ratio;
      }
    } crossScattered, crossRuns;
    for (double fraction : { 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.85, 1.0 })
    {
      const std::vector<float> deltaScattered = scattered(fraction), deltaRuns = inRuns(fraction);
      const double td = timeBlend(deltaScattered, 0.0);
      const double ts = timeBlend(deltaScattered, 1.0);
      const double tr = timeBlend(deltaRuns, 1.0);
      crossScattered.Add(fraction, ts / td);
      crossRuns.Add(fraction, tr / td);
      report.Text << "| " << fraction * 100 << " % | " << Format(ts * 1e6) << " us | " << Format(tr * 1e6) << " us | "
                  << Format(td * 1e6) << " us | " << Format(ts / td) << " x | " << Format(tr / td) << " x |\n";
      std::cout << std::left << std::setw(8) << (Format(fraction * 100) + " %") << " scattered " << std::setw(8)
                << Format(ts * 1e6) << " us  in runs " << std::setw(8) << Format(tr * 1e6) << " us  dense "
                << std::setw(8) << Format(td * 1e6) << " us\n";
    }
    const auto crossing = [](const Crossing& c) { return c.At < 0 ? std::string("none below 100 %") : "about " + Format(c.At * 100) + " %"; };
    report.Text << "\nCrossover (sparse as fast as dense): scattered " << crossing(crossScattered) << ", in runs "
                << crossing(crossRuns) << " of the points moved; MorphMesh::DefaultSparseCoverage = "
                << morphnode::MorphMesh::DefaultSparseCoverage * 100 << " %.\n";
    std::cout << "crossover: scattered " << crossing(crossScattered) << ", in runs " << crossing(crossRuns) << "\n";
  }

  // About a million points (the face tiled), all targets active, against the triad.
  {
    const size_t tiles = Smoke ? 2 : (1000000 + ict.NumPoints - 1) / ict.NumPoints;
    Face big;
    big.NumPoints = ict.NumPoints * tiles;
    for (size_t t = 0; t < tiles; ++t)
    {
      big.Neutral.insert(big.Neutral.end(), ict.Neutral.begin(), ict.Neutral.end());
    }
    for (const auto& d : ict.Deltas)
    {
      std::vector<float> tiled;
      tiled.reserve(big.NumPoints * 3);
      for (size_t t = 0; t < tiles; ++t)
      {
        tiled.insert(tiled.end(), d.begin(), d.end());
      }
      big.Deltas.push_back(std::move(tiled));
    }
    const MorphAttribute<float> dense = BuildAttribute(big, 0.0);
    std::vector<float> o(big.NumPoints * 3);
    const std::vector<double> w = Weights(big.Deltas.size(), AllTargets(big));
    const double bytes = static_cast<double>(big.NumPoints) * 3 * sizeof(float) * (big.Deltas.size() + 2);
    // The triad streams as many bytes as the kernel does. Sized as STREAM's usual 3 x 64 MiB
    // it read 80 GB/s here, against 60-65 GB/s from 3 x 128 MiB up (the sweep below): this
    // VM hides its caches from the guest (no /sys cache entries), and one of them holds part
    // of a 192 MiB working set. STREAM asks for arrays well beyond every cache; a triad over
    // the kernel's own working set is in the kernel's regime whatever those caches are.
    const size_t triadBytes = static_cast<size_t>(bytes / 3);
    // Allocated anew each round: on this VM the bandwidth one set of pages gets varied from
    // run to run by up to 40 %, so no single placement decides.
    std::unique_ptr<Triad> triad;
    const Alternated t({ [&] { KernelBlend(dense, w, o, 1); }, [&] { triad->Run(1); },
                         [&] { KernelBlend(dense, w, o, 2); }, [&] { triad->Run(2); } },
      0.3, 8, [&] { triad.reset(); triad = std::make_unique<Triad>(triadBytes); });
    const double t1 = t.Time(0), t2 = t.Time(2);
    const double triad1 = triad->Bandwidth(t.Time(1)), triad2 = triad->Bandwidth(t.Time(3));
    // Kernel bandwidth / triad bandwidth = triad time / kernel time * bytes ratio.
    const double share1 = bytes / triad->Bandwidth(1.0) / t.Ratio(0, 1);
    const double share2 = bytes / triad->Bandwidth(1.0) / t.Ratio(2, 3);
    report.Text << "\n**" << big.NumPoints << " points, all " << big.Deltas.size()
                << " targets active, dense**\n\n| measure | value | goal |\n| --- | --- | --- |\n";
    std::cout << "\nMillion-point face\n";
    report.Row("bytes streamed per frame (neutral, " + std::to_string(big.Deltas.size()) + " targets, output)", bytes / 1e6, "MB");
    report.Row("time per frame, 1 thread", t1 * 1e3, "ms");
    report.Row("time per frame, 2 threads", t2 * 1e3, "ms");
    report.Row("triad bandwidth (3 x " + Format(triadBytes / 1048576.0) + " MiB), 1 thread", triad1 / 1e9, "GB/s");
    report.Row("triad bandwidth (3 x " + Format(triadBytes / 1048576.0) + " MiB), 2 threads", triad2 / 1e9, "GB/s");
    report.Row("kernel bandwidth / triad bandwidth, 1 thread", share1 * 100, "%");
    report.Row("kernel bandwidth / triad bandwidth, 2 threads", share2 * 100, "%", ">= 75 %");
    report.Goal(std::to_string(big.NumPoints) + "-point face, all targets, dense, 2 threads: kernel bandwidth / triad bandwidth", share2 * 100, "%", ">= 75 %", share2 >= 0.75);
  }

  // Where the machine's caches end: the triad's bandwidth against its arrays' size.
  {
    report.Text << "\n**Triad bandwidth against array size (2 threads)**\n\n| arrays | working set | bandwidth |\n| --- | --- | --- |\n";
    std::cout << "\nTriad bandwidth against array size\n";
    for (size_t mib : { 16, 64, 128, 256 })
    {
      std::unique_ptr<Triad> triad;
      const size_t bytesPerArray = Smoke ? (size_t(1) << 16) : mib << 20;
      const Alternated t({ [&] { triad->Run(2); } }, 0.2, 3,
        [&] { triad.reset(); triad = std::make_unique<Triad>(bytesPerArray); });
      const double gbs = triad->Bandwidth(t.Time(0)) / 1e9;
      report.Text << "| 3 x " << mib << " MiB | " << 3 * mib << " MiB | " << Format(gbs) << " GB/s |\n";
      std::cout << std::left << std::setw(14) << ("3 x " + std::to_string(mib) + " MiB") << Format(gbs) << " GB/s\n";
    }
  }

  if (!markdown.empty())
  {
    std::ofstream md(markdown);
    md << "<!-- generated by BenchMorph --markdown; do not edit -->\n"
       << "Machine: " << ReadField("/proc/cpuinfo", "model name") << ", " << std::thread::hardware_concurrency()
       << " cores; vtkSMPTools backend " << vtkSMPTools::GetBackend() << ". Load average (1/5/15 min) at start "
       << loadBefore << ", at end " << LoadAverage() << ".\n"
       << (Smoke ? "\n**Smoke run: the figures below are single untimed calls, not measurements.**\n" : "")
       << "\n**Goals**\n\n| goal | measured | bound | |\n| --- | --- | --- | --- |\n"
       << report.Goals.str() << report.Text.str();
  }
  return 0;
}
