// SPDX-License-Identifier: BSD-3-Clause
// The morph-stage benchmark suite: every figure is a ratio of two timings taken in the
// same run, on the same face and weights.
//
//   BenchMorph [--smoke] [--markdown FILE] [--face FILE.glb] [--java3d DIR | --no-java3d]
//             [--java3d-rounds N] [--java3d-only] [--head FILE.glb] [--head-only]
//
// Baselines: a naive Java3D-style blend (absolute shapes, every target, no skipping);
// VTK 9.1's glTF morphing loop (vtkGLTFReader's ApplyMorphingToDataArray, replicated:
// dense, virtual GetTuple per component); a plain hand-written skip-zero loop over flat
// float arrays; the machine's memory bandwidth (STREAM-like triad, measured here); and
// the raw kernel under the whole VTK pipeline. Against the paper's own engine, Java3D's
// Morph node runs in the same invocation (RunJava3DMorph.sh next to this file starts the
// Java3D harness in DIR, a separate JVM process; BenchMorph reads the timings, geometry and
// exact weights it writes and times vtkMorphNodeFilter on them right after it, round after
// round); without Java or Java3D that section is skipped with a message. A whole head (the
// ICT head, 11 parts, or --head) morphed as its parts against the same points and targets as
// one mesh, Update against Update (docs/scene.md). --smoke runs every
// case once, briefly, for CI (Java3D never): it checks that the suite runs, and asserts
// nothing about time.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "../Cxx/MorphNodeMergeParts.h"

#include "base/Error.h"
#include "base/Text.h"
#include "morph/MorphAttribute.h"
#include "morph/MorphMesh.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPointData.h"
#include "vtkPointSetAlgorithm.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h> // WEXITSTATUS of the Java3D script

// Set by Testing/Benchmarks/CMakeLists.txt: this folder (RunJava3DMorph.sh) and the Java3D
// harness (--java3d overrides it).
#ifndef MORPHNODE_BENCHMARK_DIR
#define MORPHNODE_BENCHMARK_DIR "."
#endif
#ifndef MORPHNODE_JAVA3D_HARNESS_DIR
#define MORPHNODE_JAVA3D_HARNESS_DIR ""
#endif

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

/// About the cheapest filter VTK can run: it hands on the first input's points and cells,
/// no arrays. Its Update is the executive's own cost per time step, the floor under any
/// filter's (vtkMorphNodeFilter's included). Like the morph filter it takes any number of
/// connections on port 0, so that the floor of the Java3D form (one per geometry) shows.
class PassPoints : public vtkPointSetAlgorithm
{
public:
  static PassPoints* New();
  vtkTypeMacro(PassPoints, vtkPointSetAlgorithm);

protected:
  int FillInputPortInformation(int port, vtkInformation* info) override
  {
    this->Superclass::FillInputPortInformation(port, info);
    info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
    return 1;
  }
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
  reader->SetMeshIndex(0);                                         // one mesh, one vtkPolyData
  reader->SetNormalsMode(vtkMorphTargetReader::NORMALS_FROM_FILE); // positions only
  reader->Update();
  vtkPolyData* pd = reader->GetOutput();
  Face face;
  face.NumPoints = static_cast<size_t>(pd->GetNumberOfPoints());
  auto flat = [](vtkDataArray* a)
  {
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
    face.Deltas.push_back(
      flat(pd->GetPointData()->GetArray(("target" + std::to_string(k) + "_position").c_str())));
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
MORPHNODE_BENCH_CLONES void PlainSkipZero(
  const Face& face, const std::vector<double>& w, std::vector<float>& out)
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
        [&](vtkIdType lo, vtkIdType hi)
        { range(static_cast<size_t>(lo), static_cast<size_t>(hi)); });
    }
    Sink = A[N / 2];
  }
  /// Bytes per second from the seconds one Run took (STREAM's count: 3 arrays).
  double Bandwidth(double seconds) const { return 3.0 * N * sizeof(float) / seconds; }
};

/// Blends with the core kernel: one thread, or vtkSMPTools over points with the grain the
/// VTK module uses (vtkMorphModelAdapter::Blend), on the pool of both cores.
void KernelBlend(const MorphAttribute<float>& a, const std::vector<double>& w,
  std::vector<float>& out, int threads)
{
  if (threads == 1)
  {
    a.Blend(w.data(), w.size(), out.data(), 0, a.GetNumberOfPoints());
    return;
  }
  vtkSMPTools::For(0, static_cast<vtkIdType>(a.GetNumberOfPoints()), 1024,
    [&](vtkIdType begin, vtkIdType end) {
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
  void Goal(const std::string& what, double value, const std::string& unit,
    const std::string& bound, bool pass)
  {
    this->Goals << "| " << what << " | " << Format(value) << " " << unit << " | " << bound << " | "
                << (pass ? "**pass**" : "**MISS**") << " |\n";
  }
  /// A goal that could not be measured in this run.
  void Skipped(const std::string& what, const std::string& bound, const std::string& why)
  {
    this->Goals << "| " << what << " | not measured: " << why << " | " << bound << " | skipped |\n";
  }
  void Row(
    const std::string& what, double value, const std::string& unit, const std::string& goal = "")
  {
    std::ostringstream v;
    v << std::setprecision(3) << value;
    this->Text << "| " << what << " | " << v.str() << " " << unit << " | " << goal << " |\n";
    std::cout << std::left << std::setw(78) << what << std::setw(12) << v.str() << unit
              << (goal.empty() ? "" : "   (goal: " + goal + ")") << "\n";
  }
};
// --- Java3D's Morph, the paper's engine, side by side -------------------------------

/// The Java3D harness's geometry (face14.bin, little-endian, see the harness's README):
/// absolute shapes, the neutral first, and the triangles.
struct Face14
{
  size_t NumPoints = 0;
  std::vector<std::string> Names;
  std::vector<int32_t> Triangles; // 3 point ids each
  std::vector<std::vector<float>> Positions, Normals;
};

Face14 ReadFace14(const std::string& file)
{
  const std::string bytes = morphnode::text::ReadFile(file, "Java3D geometry");
  size_t at = 0;
  const auto take = [&](void* to, size_t n)
  {
    if (n > bytes.size() - at)
    {
      throw morphnode::InputError("Java3D geometry '" + file + "' is truncated");
    }
    std::memcpy(to, bytes.data() + at, n);
    at += n;
  };
  char magic[8];
  take(magic, 8);
  int32_t nv = 0, ntri = 0, nt = 0;
  take(&nv, 4);
  take(&ntri, 4);
  take(&nt, 4);
  if (std::memcmp(magic, "MORPH14", 7) != 0 || nv <= 0 || ntri <= 0 || nt <= 1 || nt > 1024)
  {
    throw morphnode::InputError("'" + file + "' is not a MORPH14 geometry file");
  }
  Face14 face;
  face.NumPoints = static_cast<size_t>(nv);
  for (int32_t t = 0; t < nt; ++t)
  {
    int32_t length = 0;
    take(&length, 4);
    if (length < 0 || length > 4096)
    {
      throw morphnode::InputError("'" + file + "' has a bad target name");
    }
    std::string name(static_cast<size_t>(length), ' ');
    take(name.data(), name.size());
    face.Names.push_back(name);
  }
  face.Triangles.resize(3 * static_cast<size_t>(ntri));
  take(face.Triangles.data(), face.Triangles.size() * 4);
  for (int32_t id : face.Triangles)
  {
    if (id < 0 || id >= nv)
    {
      throw morphnode::InputError("'" + file + "' has a triangle outside its points");
    }
  }
  for (int32_t t = 0; t < nt; ++t)
  {
    std::vector<float> p(3 * face.NumPoints);
    take(p.data(), p.size() * 4);
    // Area-weighted vertex normals, as Morph14.java gives them to Java3D (same arithmetic).
    std::vector<double> n(p.size(), 0.0);
    for (size_t f = 0; f < face.Triangles.size(); f += 3)
    {
      const size_t a = 3 * static_cast<size_t>(face.Triangles[f]);
      const size_t b = 3 * static_cast<size_t>(face.Triangles[f + 1]);
      const size_t c = 3 * static_cast<size_t>(face.Triangles[f + 2]);
      const double ux = p[b] - p[a], uy = p[b + 1] - p[a + 1], uz = p[b + 2] - p[a + 2];
      const double vx = p[c] - p[a], vy = p[c + 1] - p[a + 1], vz = p[c + 2] - p[a + 2];
      const double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
      for (size_t v : { a, b, c })
      {
        n[v] += cx;
        n[v + 1] += cy;
        n[v + 2] += cz;
      }
    }
    std::vector<float> unit(p.size());
    for (size_t v = 0; v < p.size(); v += 3)
    {
      double l = std::sqrt(n[v] * n[v] + n[v + 1] * n[v + 1] + n[v + 2] * n[v + 2]);
      l = l == 0 ? 1 : l;
      for (size_t c = 0; c < 3; ++c)
      {
        unit[v + c] = static_cast<float>(n[v + c] / l);
      }
    }
    face.Positions.push_back(std::move(p));
    face.Normals.push_back(std::move(unit));
  }
  return face;
}

/// The harness's weights (weights.bin): speech warm-up, speech timed, all-14 warm-up,
/// all-14 timed; each frame one weight per geometry, neutral first.
std::vector<std::vector<std::vector<double>>> ReadJava3DWeights(
  const std::string& file, size_t numTargets)
{
  const std::string bytes = morphnode::text::ReadFile(file, "Java3D weights");
  std::vector<std::vector<std::vector<double>>> blocks;
  size_t at = 0;
  for (int b = 0; b < 4; ++b)
  {
    int32_t frames = 0;
    if (bytes.size() - at < 4)
    {
      throw morphnode::InputError("Java3D weights '" + file + "' are truncated");
    }
    std::memcpy(&frames, bytes.data() + at, 4);
    at += 4;
    const size_t size = static_cast<size_t>(std::max(frames, 0)) * numTargets * 8;
    if (frames <= 0 || size > bytes.size() - at)
    {
      throw morphnode::InputError("Java3D weights '" + file + "' are truncated");
    }
    std::vector<std::vector<double>> block(
      static_cast<size_t>(frames), std::vector<double>(numTargets));
    for (auto& w : block)
    {
      std::memcpy(w.data(), bytes.data() + at, numTargets * 8);
      at += numTargets * 8;
    }
    blocks.push_back(std::move(block));
  }
  return blocks;
}

/// Java3D's median time per Morph.setWeights (ms) of a geometry kind and weight pattern,
/// from the harness's report, e.g. "indexed/byref (11248)  speech  median   0.313 ...".
double Java3DMedianMs(
  const std::string& report, const std::string& kind, const std::string& pattern)
{
  std::istringstream in(report);
  std::string line;
  while (std::getline(in, line))
  {
    if (line.rfind(kind + " ", 0) != 0 || line.find(" " + pattern + " ") == std::string::npos)
    {
      continue;
    }
    std::istringstream fields(line.substr(line.find("median") + 6));
    std::string token;
    double ms = 0.0;
    if (fields >> token && morphnode::text::ParseNumber(token, ms) && ms > 0.0)
    {
      return ms;
    }
  }
  throw morphnode::InputError("the Java3D report has no " + kind + " " + pattern + " median");
}

/// The first line of `text` starting with `prefix`, or "".
std::string LineStarting(const std::string& text, const std::string& prefix)
{
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
  {
    if (line.rfind(prefix, 0) == 0)
    {
      return line;
    }
  }
  return "";
}

struct Java3DRun
{
  double SpeechMs = 0.0, AllMs = 0.0; // Morph.setWeights, indexed/byref
  std::string Report;
};

/// Runs the harness once through RunJava3DMorph.sh. False, with the reason, when it is
/// skipped (no Java, no Java3D, ...); throws when it fails.
bool RunJava3D(const std::string& harness, const std::string& face, const std::string& out,
  Java3DRun& run, std::string& why)
{
  const std::string script = std::string(MORPHNODE_BENCHMARK_DIR) + "/RunJava3DMorph.sh";
  const std::string command = "bash '" + script + "' '" + harness + "' '" + face + "' '" + out +
    "' 500 300 2> '" + out + ".skip'";
  const int status = std::system(command.c_str());
  const int code = status == -1 ? -1 : WEXITSTATUS(status);
  if (code == 77)
  {
    std::ifstream reason(out + ".skip");
    std::getline(reason, why);
    return false;
  }
  if (code != 0)
  {
    throw morphnode::InputError("the Java3D harness failed (exit " + std::to_string(code) +
      "); see " + out + "/java3d.err and " + out + ".skip");
  }
  run.Report = morphnode::text::ReadFile(out + "/java3d.txt", "Java3D report");
  run.SpeechMs = Java3DMedianMs(run.Report, "indexed/byref", "speech");
  run.AllMs = Java3DMedianMs(run.Report, "indexed/byref", "all14");
  return true;
}

/// vtkMorphNodeFilter on Java3D's geometry, in both of its input forms (the Java3D form
/// as 14 connections and as one vtkPartitionedDataSet of the 14 geometries), and VTK's
/// floor under each.
struct Java3DScene
{
  Face14 Face;
  std::vector<std::vector<std::vector<double>>> Weights;
  vtkSmartPointer<vtkPolyData> OneInput;                // glTF form: target arrays
  std::vector<vtkSmartPointer<vtkPolyData>> Geometries; // Java3D form: one per geometry
  vtkNew<vtkPartitionedDataSet> Shapes;                 // Java3D form in one connection
  vtkNew<vtkMorphNodeFilter> Relative, Absolute, Partitioned;
  vtkNew<PassPoints> FloorOne, FloorAll;

  Java3DScene(Face14 face, std::vector<std::vector<std::vector<double>>> weights)
    : Face(std::move(face))
    , Weights(std::move(weights))
  {
    const vtkIdType n = static_cast<vtkIdType>(this->Face.NumPoints);
    const auto floats = [n](const char* name, const std::vector<float>& values)
    {
      auto array = vtkSmartPointer<vtkFloatArray>::New();
      array->SetName(name);
      array->SetNumberOfComponents(3);
      array->SetNumberOfTuples(n);
      std::copy(values.begin(), values.end(), array->GetPointer(0));
      return array;
    };
    vtkNew<vtkCellArray> cells;
    for (size_t f = 0; f < this->Face.Triangles.size(); f += 3)
    {
      const vtkIdType ids[3] = { this->Face.Triangles[f], this->Face.Triangles[f + 1],
        this->Face.Triangles[f + 2] };
      cells->InsertNextCell(3, ids);
    }
    vtkNew<vtkStringArray> names;
    names->SetName("TargetNames");
    for (const auto& name : this->Face.Names)
    {
      names->InsertNextValue(name);
    }
    for (size_t t = 0; t < this->Face.Positions.size(); ++t)
    {
      auto shape = vtkSmartPointer<vtkPolyData>::New();
      vtkNew<vtkPoints> points;
      points->SetData(floats(nullptr, this->Face.Positions[t]));
      shape->SetPoints(points);
      shape->GetPointData()->SetNormals(floats("Normals", this->Face.Normals[t]));
      if (t == 0)
      {
        shape->SetPolys(cells);
        shape->GetFieldData()->AddArray(names);
      }
      this->Geometries.push_back(shape);
      this->Absolute->AddInputData(0, shape);
      this->Shapes->SetPartition(static_cast<unsigned int>(t), shape);
      this->FloorAll->AddInputData(0, shape);
    }
    // The same geometry as deltas (target - neutral, in float as the filter's own
    // conversion computes them), so both forms blend the same numbers.
    this->OneInput = vtkSmartPointer<vtkPolyData>::New();
    this->OneInput->ShallowCopy(this->Geometries[0]);
    for (size_t t = 1; t < this->Face.Positions.size(); ++t)
    {
      std::vector<float> dp(this->Face.Positions[t]), dn(this->Face.Normals[t]);
      for (size_t i = 0; i < dp.size(); ++i)
      {
        dp[i] -= this->Face.Positions[0][i];
        dn[i] -= this->Face.Normals[0][i];
      }
      const std::string k = std::to_string(t - 1);
      this->OneInput->GetPointData()->AddArray(floats(("target" + k + "_position").c_str(), dp));
      this->OneInput->GetPointData()->AddArray(floats(("target" + k + "_normal").c_str(), dn));
    }
    this->Relative->SetInputData(this->OneInput);
    this->Partitioned->SetInputData(this->Shapes);
    this->FloorOne->SetInputData(this->OneInput);
    for (vtkMorphNodeFilter* filter :
      { this->Relative.Get(), this->Absolute.Get(), this->Partitioned.Get() })
    {
      filter->SetWeightModeToStrict(); // Java3D's rule; its negative neutral weights included
    }
  }

  /// One frame as a program drives the node: every weight set, then an update.
  static void Step(vtkMorphNodeFilter* filter, const std::vector<double>& w)
  {
    for (size_t t = 0; t < w.size(); ++t)
    {
      filter->SetWeight(static_cast<int>(t), w[t]);
    }
    filter->Update();
  }

  /// Seconds per frame as the harness measures Java3D: a warm-up pass, then every frame
  /// timed on its own, the median; here the median over `passes` such passes.
  static double TimeFrames(const std::function<void(const std::vector<double>&)>& step,
    const std::vector<std::vector<double>>& warmup, const std::vector<std::vector<double>>& timed,
    int passes)
  {
    if (Smoke)
    {
      step(timed.front());
      return 0.0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    for (const auto& w : warmup)
    {
      step(w);
    }
    std::vector<double> medians;
    std::vector<double> times(timed.size());
    for (int pass = 0; pass < passes; ++pass)
    {
      for (size_t f = 0; f < timed.size(); ++f)
      {
        const auto t0 = std::chrono::steady_clock::now();
        step(timed[f]);
        times[f] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
      std::nth_element(
        times.begin(), times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2), times.end());
      medians.push_back(times[times.size() / 2]);
    }
    std::nth_element(medians.begin(),
      medians.begin() + static_cast<std::ptrdiff_t>(medians.size() / 2), medians.end());
    return medians[medians.size() / 2];
  }

  /// Largest distance of a blended point from Java3D's sum_t w_t G_t (in double).
  double MaxError(vtkMorphNodeFilter* filter, const std::vector<double>& w) const
  {
    Step(filter, w);
    vtkPointSet* out = vtkPointSet::SafeDownCast(filter->GetOutputDataObject(0));
    if (!out || static_cast<size_t>(out->GetNumberOfPoints()) != this->Face.NumPoints)
    {
      return std::numeric_limits<double>::infinity();
    }
    double worst = 0.0;
    for (size_t i = 0; i < this->Face.NumPoints; ++i)
    {
      double p[3];
      out->GetPoint(static_cast<vtkIdType>(i), p);
      for (size_t c = 0; c < 3; ++c)
      {
        double ref = 0.0;
        for (size_t t = 0; t < w.size(); ++t)
        {
          ref += w[t] * this->Face.Positions[t][3 * i + c];
        }
        worst = std::max(worst, std::abs(ref - p[c]));
      }
    }
    return worst;
  }
};

/// The Java3D section: rounds of (Java3D's harness, then the morph filter on its
/// geometry and weights); the goals read the median of the per-round ratios.
void CompareWithJava3D(
  Report& report, const std::string& harness, const std::string& face, int rounds)
{
  const std::string speechGoal =
    "ICT 14 geometries with normals, speech frames (Java3D's weights): "
    "Java3D Morph.setWeights / vtkMorphNodeFilter Update (one input)";
  const std::string allGoal = "ICT 14 geometries with normals, all 14 active: "
                              "Java3D Morph.setWeights / vtkMorphNodeFilter Update (one input)";
  // The Java3D form: the 14 geometries as 14 connections, and as one vtkPartitionedDataSet.
  const std::string forms[2] = { "14 connections", "14 geometries in one vtkPartitionedDataSet" };
  const auto java3dGoal = [](int pattern, const std::string& form)
  {
    return std::string("ICT 14 geometries with normals, ") +
      (pattern == 0 ? "speech frames" : "all 14 active") +
      ": Java3D Morph.setWeights / vtkMorphNodeFilter Update (Java3D form, " + form + ")";
  };
  report.Text << "\n**Against Java3D's Morph (the paper's engine), same run**\n\n";
  std::cout << "\nJava3D's Morph, side by side\n";
  const auto skip = [&](const std::string& why)
  {
    std::cout << "Java3D comparison skipped: " << why << "\n";
    report.Text << "Skipped: " << why << ".\n";
    report.Skipped(speechGoal, ">= 10 x", why);
    report.Skipped(allGoal, ">= 15 x", why);
    for (const std::string& form : forms)
    {
      report.Skipped(java3dGoal(0, form), ">= 8 x", why);
      report.Skipped(java3dGoal(1, form), ">= 12 x", why);
    }
  };
  if (harness.empty() && !Smoke)
  {
    skip("not asked for (--no-java3d)");
    return;
  }
  if (Smoke)
  {
    // The filter's side on a small made-up geometry, so that CI runs its code.
    Face14 small;
    small.NumPoints = 4;
    small.Triangles = { 0, 1, 2, 0, 2, 3 };
    for (int t = 0; t < 14; ++t)
    {
      small.Names.push_back(t == 0 ? "Neutral" : "shape" + std::to_string(t));
      small.Positions.push_back({ 0, 0, 0, 1, 0, 0, 1, 1, 0.1f * t, 0, 1, 0 });
      small.Normals.push_back({ 0, 0, 1, 0, 0, 1, 0, 0.1f * t, 1, 0, 0, 1 });
    }
    std::vector<double> w(14, 0.1); // the neutral's 1 - 1.3 < 0, as in Java3D's speech frames
    w[0] = -0.3;
    Java3DScene scene(small, { { w }, { w }, { w }, { w } });
    const double error = std::max({ scene.MaxError(scene.Relative, w),
      scene.MaxError(scene.Absolute, w), scene.MaxError(scene.Partitioned, w) });
    std::cout << "smoke: the filter on a made-up 14-geometry face, largest error " << error << "\n";
    if (!(error < 1e-5))
    {
      throw morphnode::InputError(
        "the morph filter does not blend Java3D's weights as Java3D does");
    }
    skip("smoke run (the Java3D harness takes half a minute a round)");
    return;
  }
  std::string out = "/tmp/BenchMorph-java3d-XXXXXX";
  if (!mkdtemp(out.data()))
  {
    skip("no temporary folder");
    return;
  }
  out += "/run";
  std::unique_ptr<Java3DScene> scene;
  struct Round
  {
    Java3DRun Java;
    double Relative[2], Absolute[2], Partitioned[2], FloorOne[2], FloorAll[2]; // speech, all 14
  };
  std::vector<Round> done;
  for (int r = 0; r < rounds; ++r)
  {
    Round round{};
    std::string why;
    std::cout << "round " << r + 1 << " of " << rounds << ": Java3D harness ... " << std::flush;
    if (!RunJava3D(harness, face, out, round.Java, why))
    {
      skip(why);
      return;
    }
    std::cout << round.Java.SpeechMs << " / " << round.Java.AllMs << " ms; vtkMorphNodeFilter ... "
              << std::flush;
    if (!scene)
    {
      Face14 geometry = ReadFace14(out + "/face14.bin");
      auto weights = ReadJava3DWeights(out + "/weights.bin", geometry.Names.size());
      scene = std::make_unique<Java3DScene>(std::move(geometry), std::move(weights));
    }
    Java3DScene& s = *scene;
    for (int pattern = 0; pattern < 2; ++pattern)
    {
      const auto& warmup = s.Weights[2 * static_cast<size_t>(pattern)];
      const auto& timed = s.Weights[2 * static_cast<size_t>(pattern) + 1];
      round.Relative[pattern] = Java3DScene::TimeFrames(
        [&](const std::vector<double>& w) { Java3DScene::Step(s.Relative, w); }, warmup, timed, 3);
      round.Absolute[pattern] = Java3DScene::TimeFrames(
        [&](const std::vector<double>& w) { Java3DScene::Step(s.Absolute, w); }, warmup, timed, 3);
      round.Partitioned[pattern] = Java3DScene::TimeFrames([&](const std::vector<double>& w)
        { Java3DScene::Step(s.Partitioned, w); },
        warmup, timed, 3);
      round.FloorOne[pattern] = Java3DScene::TimeFrames(
        [&](const std::vector<double>&)
        {
          s.FloorOne->Modified();
          s.FloorOne->Update();
        },
        warmup, timed, 1);
      round.FloorAll[pattern] = Java3DScene::TimeFrames(
        [&](const std::vector<double>&)
        {
          s.FloorAll->Modified();
          s.FloorAll->Update();
        },
        warmup, timed, 1);
    }
    std::cout << round.Relative[0] * 1e6 << " / " << round.Relative[1] * 1e6 << " us (one input), "
              << round.Absolute[0] * 1e6 << " / " << round.Absolute[1] * 1e6
              << " us (14 connections), " << round.Partitioned[0] * 1e6 << " / "
              << round.Partitioned[1] * 1e6 << " us (one vtkPartitionedDataSet)\n";
    done.push_back(round);
  }
  Java3DScene& s = *scene;
  const auto median = [&](const std::function<double(const Round&)>& value)
  {
    std::vector<double> v;
    for (const Round& round : done)
    {
      v.push_back(value(round));
    }
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const std::string header = LineStarting(done.back().Java.Report, "Java3D ");
  const std::string patterns = LineStarting(done.back().Java.Report, "patterns: ");
  std::error_code ignored;
  report.Text
    << "Java3D's harness (" << std::filesystem::weakly_canonical(harness, ignored).string()
    << ", `RunJava3DMorph.sh`, a JVM process started by BenchMorph "
    << "before each of " << done.size()
    << " rounds) blends the ICT face's neutral and 13 ARKit shapes, " << s.Face.NumPoints
    << " points with area-weighted normals, as absolute geometries (indexed, by reference); "
    << "its time is the median wall time of `Morph.setWeights` per frame (the blend of coordinates "
       "and normals "
    << "without renormalizing them, bounds, change message). Right after it, vtkMorphNodeFilter "
       "blends the same "
    << "geometries with the exact weights Java3D used (Strict mode: Java3D's rule, negative "
       "neutral weights "
    << "included), renormalizing the normals; its time is the median over frames of setting the 14 "
       "weights and "
    << "Update. Ratios are medians of the per-round ratios. " << header << "; " << patterns
    << ".\n\n"
    << "| measure | value | goal |\n| --- | --- | --- |\n";
  const char* tags[2] = { "speech frames", "all 14 active" };
  for (int p = 0; p < 2; ++p)
  {
    const auto javaMs = [p](const Round& r) { return p == 0 ? r.Java.SpeechMs : r.Java.AllMs; };
    const double ratioOne =
      median([&](const Round& r) { return javaMs(r) * 1e-3 / r.Relative[p]; });
    const double ratioAll =
      median([&](const Round& r) { return javaMs(r) * 1e-3 / r.Absolute[p]; });
    const double ratioShapes =
      median([&](const Round& r) { return javaMs(r) * 1e-3 / r.Partitioned[p]; });
    const std::string java3dBound = p == 0 ? ">= 8 x" : ">= 12 x";
    const double java3dMin = p == 0 ? 8.0 : 12.0;
    const std::string bound = p == 0 ? ">= 10 x" : ">= 15 x";
    const std::string tag = tags[p];
    report.Row(
      tag + ": Java3D Morph.setWeights, indexed/byref: time per frame", median(javaMs) * 1e3, "us");
    report.Row(tag + ": vtkMorphNodeFilter Update, one input (glTF form): time per frame",
      median([p](const Round& r) { return r.Relative[p]; }) * 1e6, "us");
    report.Row(tag + ": vtkMorphNodeFilter Update, 14 connections (Java3D form): time per frame",
      median([p](const Round& r) { return r.Absolute[p]; }) * 1e6, "us");
    report.Row(tag +
        ": vtkMorphNodeFilter Update, 14 geometries in one vtkPartitionedDataSet (Java3D form): "
        "time per frame",
      median([p](const Round& r) { return r.Partitioned[p]; }) * 1e6, "us");
    report.Row(tag + ": VTK's floor (a filter passing the points on), one input: time per frame",
      median([p](const Round& r) { return r.FloorOne[p]; }) * 1e6, "us");
    report.Row(tag + ": VTK's floor, 14 connections: time per frame",
      median([p](const Round& r) { return r.FloorAll[p]; }) * 1e6, "us");
    report.Row(tag + ": Java3D / vtkMorphNodeFilter, one input", ratioOne, "x", bound);
    report.Row(tag + ": Java3D / vtkMorphNodeFilter, 14 connections", ratioAll, "x", java3dBound);
    report.Row(tag + ": Java3D / vtkMorphNodeFilter, one vtkPartitionedDataSet", ratioShapes, "x",
      java3dBound);
    report.Goal(
      p == 0 ? speechGoal : allGoal, ratioOne, "x", bound, ratioOne >= (p == 0 ? 10.0 : 15.0));
    report.Goal(java3dGoal(p, forms[0]), ratioAll, "x", java3dBound, ratioAll >= java3dMin);
    report.Goal(java3dGoal(p, forms[1]), ratioShapes, "x", java3dBound, ratioShapes >= java3dMin);
  }
  const auto& lastSpeech = s.Weights[1].back();
  report.Row("last speech frame: largest distance of a point from Java3D's sum w_t G_t, one input",
    s.MaxError(s.Relative, lastSpeech), "m");
  report.Row(
    "last speech frame: largest distance of a point from Java3D's sum w_t G_t, 14 connections",
    s.MaxError(s.Absolute, lastSpeech), "m");
  report.Row("last speech frame: largest distance of a point from Java3D's sum w_t G_t, one "
             "vtkPartitionedDataSet",
    s.MaxError(s.Partitioned, lastSpeech), "m");
}
// --- a whole head: its parts against one mesh ---------------------------------------

/// The head read as its parts (vtkMorphTargetReader's collection, positions and normals,
/// world space) and the same points and targets as one vtkPolyData; each through its own
/// vtkMorphNodeFilter, a weight change and an Update per step, alternated in rounds.
void CompareHeadWithOneMesh(Report& report, const std::string& file)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  auto* head = vtkCompositeDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  const std::vector<vtkPolyData*> parts = morphnode_test::PolyDataLeaves(head);
  if (parts.empty())
  {
    throw morphnode::InputError("'" + file + "' could not be read as a scene");
  }
  const vtkSmartPointer<vtkPolyData> one = morphnode_test::MergeParts(head);
  vtkNew<vtkMorphNodeFilter> scene, mesh;
  scene->SetInputData(head);
  mesh->SetInputData(one);
  for (vtkMorphNodeFilter* f : { scene.GetPointer(), mesh.GetPointer() })
  {
    f->SetWeightModeToRelative();
    f->Update();
  }
  const int targets = mesh->GetNumberOfTargets() - 1;
  int withTargets = 0;
  for (vtkPolyData* part : parts)
  {
    withTargets += morphnode_test::FieldStrings(part->GetFieldData(), "TargetNames").size() > 1;
  }
  const std::string what = std::filesystem::path(file).filename().string() + " (" +
    std::to_string(one->GetNumberOfPoints()) + " points, " + std::to_string(parts.size()) +
    " parts, " + std::to_string(withTargets) + " with targets, " + std::to_string(targets) +
    " targets, positions + normals)";
  std::cout << "\nWhole head: " << what << "\n";
  report.Text << "\n**Whole head: " << what
              << "**\n\n| measure | value | goal |\n| --- | --- | --- |\n";

  // The speech frame's targets by name (ICT/ARKit, else the paper's visemes), else spread.
  std::vector<int> speech;
  for (const char* name :
    { "jawOpen", "mouthFunnel", "mouthPucker", "mouthClose", "mouthSmile_L", "mouthSmile_R",
      "mouthLowerDown_L", "mouthLowerDown_R", "A", "O", "MouthSmile", "BrowsUp" })
  {
    if (mesh->GetTargetIndex(name) > 0)
    {
      speech.push_back(mesh->GetTargetIndex(name));
    }
  }
  for (int k = 1; speech.size() < 4 && k <= targets; k += 7)
  {
    speech.push_back(k);
  }
  std::vector<int> all;
  for (int k = 1; k <= targets; ++k)
  {
    all.push_back(k);
  }
  struct Case
  {
    std::string Name;
    std::vector<int> Active;
    int Preset;
  };
  const Case cases[] = { { "speech frame", speech, vtkMorphNodeFilter::OPTIMIZER_NONE },
    { "speech frame, adjusted threshold 0.1", speech, vtkMorphNodeFilter::OPTIMIZER_ADJUSTED },
    { "all targets", all, vtkMorphNodeFilter::OPTIMIZER_NONE } };
  for (const Case& c : cases)
  {
    for (vtkMorphNodeFilter* f : { scene.GetPointer(), mesh.GetPointer() })
    {
      f->ResetWeights();
      f->SetOptimizerPreset(c.Preset);
      f->SetThreshold(0.1);
      for (size_t k = 0; k < c.Active.size(); ++k)
      {
        f->SetWeight(c.Active[k], 0.05 + 0.5 * static_cast<double>((k * 37) % 10) / 10.0);
      }
      f->Update();
    }
    int step = 0;
    const auto update = [&](vtkMorphNodeFilter* f)
    {
      f->SetWeight(c.Active[0], 0.5 + 1e-6 * (++step % 2));
      f->Update();
    };
    const Alternated t({ [&] { update(scene); }, [&] { update(mesh); } }, 0.1);
    const double ratio = t.Ratio(0, 1);
    const std::string tag = c.Name + " (" + std::to_string(c.Active.size()) + " of " +
      std::to_string(targets) + " active)";
    report.Row(
      tag + ": " + std::to_string(parts.size()) + " parts, Update per step", t.Time(0) * 1e6, "us");
    report.Row(tag + ": one mesh, Update per step", t.Time(1) * 1e6, "us");
    // The bound is for the full ICT head; other heads are reported (a small head
    // of many parts shows the fixed cost per part, about a microsecond).
    const bool ict = std::filesystem::path(file).filename() == "ict_head_full53.glb";
    report.Row(tag + ": parts / one mesh", ratio, "x", ict ? "<= 1.3 x" : "");
    if (ict)
    {
      report.Goal("ICT head, " + c.Name + ": Update of " + std::to_string(parts.size()) +
          " parts / one mesh of the same points and targets",
        ratio, "x", "<= 1.3 x", ratio <= 1.3);
    }
  }
}

void WriteMarkdown(const std::string& markdown, const Report& report, const std::string& loadBefore)
{
  if (markdown.empty())
  {
    return;
  }
  std::ofstream md(markdown);
  md << "<!-- generated by BenchMorph --markdown; do not edit -->\n"
     << "Machine: " << ReadField("/proc/cpuinfo", "model name") << ", "
     << std::thread::hardware_concurrency() << " cores; vtkSMPTools backend "
     << vtkSMPTools::GetBackend() << ". Load average (1/5/15 min) at start " << loadBefore
     << ", at end " << LoadAverage() << ".\n"
     << (Smoke ? "\n**Smoke run: the figures below are single untimed calls, not measurements.**\n"
               : "")
     << "\n**Goals**\n\n| goal | measured | bound | |\n| --- | --- | --- | --- |\n"
     << report.Goals.str() << report.Text.str();
}
} // namespace

int main(int argc, char* argv[])
{
  std::string face = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  std::string head = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
  bool headOnly = false;
  std::string markdown;
  std::string java3d = MORPHNODE_JAVA3D_HARNESS_DIR;
  int java3dRounds = 3;
  bool java3dOnly = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--smoke")
    {
      Smoke = true;
    }
    else if (arg == "--java3d" && i + 1 < argc)
    {
      java3d = argv[++i];
    }
    else if (arg == "--no-java3d")
    {
      java3d.clear();
    }
    else if (arg == "--java3d-only")
    {
      java3dOnly = true;
    }
    else if (arg == "--java3d-rounds" && i + 1 < argc && std::atoi(argv[i + 1]) > 0)
    {
      java3dRounds = std::atoi(argv[++i]);
    }
    else if (arg == "--markdown" && i + 1 < argc)
    {
      markdown = argv[++i];
    }
    else if (arg == "--face" && i + 1 < argc)
    {
      face = argv[++i];
    }
    else if (arg == "--head" && i + 1 < argc)
    {
      head = argv[++i];
    }
    else if (arg == "--head-only")
    {
      headOnly = true;
    }
    else
    {
      std::cerr << "usage: BenchMorph [--smoke] [--markdown FILE] [--face FILE.glb] [--java3d DIR "
                   "| --no-java3d]"
                   " [--java3d-rounds N] [--java3d-only] [--head FILE.glb] [--head-only]\n";
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

  // Against Java3D's Morph, the paper's engine: its harness runs in a JVM started from here.
  const auto java3dSection = [&]
  {
    try
    {
      CompareWithJava3D(report, java3d, face, java3dRounds);
    }
    catch (const std::exception& e)
    {
      std::cout << "Java3D comparison failed: " << e.what() << "\n";
      report.Text << "Failed: " << e.what() << ".\n";
      report.Skipped("Java3D comparison", "", std::string("failed: ") + e.what());
    }
  };
  if (java3dOnly)
  {
    java3dSection();
    WriteMarkdown(markdown, report, loadBefore);
    return 0;
  }
  // A whole head as parts against one mesh (the project's default head without ICT-FaceKit).
  const auto headSection = [&]
  {
    const std::string file = std::ifstream(head)
      ? head
      : std::string(MORPHNODE_BENCHMARK_DIR) + "/../../Data/DefaultFace/default_head.glb";
    try
    {
      CompareHeadWithOneMesh(report, file);
    }
    catch (const std::exception& e)
    {
      std::cout << "Whole-head comparison failed: " << e.what() << "\n";
      report.Skipped(
        "whole head as parts / one mesh", "<= 1.3 x", std::string("failed: ") + e.what());
    }
  };
  if (headOnly)
  {
    headSection();
    WriteMarkdown(markdown, report, loadBefore);
    return 0;
  }

  const MorphAttribute<float> kernel =
    BuildAttribute(ict, morphnode::MorphMesh::DefaultSparseCoverage);
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
    const double vtk =
      TimePerCall([&] { result = VTKGLTFLoop(origin, wf, vtkTargets); }, Smoke ? 0 : 1.0);
    // Pipeline: a weight change and an Update per step, as a time source would drive it;
    // timed in rounds alternated with the raw kernel it is compared with.
    int step = 0;
    for (size_t k = 0; k < active.size(); ++k)
    {
      filter->SetWeight(static_cast<int>(active[k] + 1), w[active[k] + 1]);
    }
    const Alternated alternated({ [&] { KernelBlend(kernel, w, out, 2); },
                                  [&]
                                  {
                                    filter->SetWeight(static_cast<int>(active[0] + 1),
                                      w[active[0] + 1] + 1e-6 * (++step % 2));
                                    filter->Update();
                                  },
                                  [&]
                                  {
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
      report.Goal("ICT speech frame: VTK 9.1 glTF morphing loop / core kernel (1 thread)",
        vtk / ours1, "x", ">= 150 x", vtk / ours1 >= 150);
      report.Goal("ICT speech frame: core kernel / plain skip-zero loop (1 thread)", ours1 / plain,
        "x", "<= 1.3 x", ours1 / plain <= 1.3);
    }
    // The issue's goal, in its words: "the VTK pipeline adds at most 2 times the raw kernel
    // time", i.e. Update - kernel <= 2 kernel. The whole Update against the kernel is reported
    // beside it (a row, not a goal): VTK's executive alone costs about 0.6 kernels here.
    report.Goal(
      "ICT " + caseName + ": time the VTK pipeline adds / raw kernel (both vtkSMPTools, 2 threads)",
      pipelineRatio - 1.0, "x", "<= 2 x", pipelineRatio - 1.0 <= 2.0);
    report.Text << "\n**ICT face, " << tag
                << "**\n\n| measure | value | goal |\n| --- | --- | --- |\n";
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
    report.Row("time the VTK pipeline adds / core kernel (both vtkSMPTools, 2 threads)",
      pipelineRatio - 1.0, "x", "<= 2 x");
    report.Row(
      "vtkMorphNodeFilter Update / core kernel (both vtkSMPTools, 2 threads)", pipelineRatio, "x");
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
    const MorphAttribute<float> big =
      BuildAttribute(doubled, morphnode::MorphMesh::DefaultSparseCoverage);
    const std::vector<size_t> active = SpeechTargets(ict);
    const std::vector<double> w1 = Weights(ict.Deltas.size(), active);
    const std::vector<double> w2 = Weights(doubled.Deltas.size(), active);
    const Alternated t(
      { [&] { KernelBlend(kernel, w1, out, 1); }, [&] { KernelBlend(big, w2, out, 1); } }, 0.08,
      12);
    const double t1 = t.Time(0), t2 = t.Time(1);
    const double change = std::abs(t.Ratio(1, 0) - 1.0);
    report.Goal("ICT speech frame: time change from doubling the inactive targets (53 -> 106)",
      change * 100, "%", "< 5 %", change < 0.05);
    report.Text
      << "\n**Inactive targets cost nothing**\n\n| measure | value | goal |\n| --- | --- | --- |\n";
    std::cout << "\nInactive targets\n";
    report.Row("speech frame, 53 targets: time per frame", t1 * 1e6, "us");
    report.Row("speech frame, 106 targets: time per frame", t2 * 1e6, "us");
    report.Row(
      "speech frame, 106 targets / 53 targets (same " + std::to_string(active.size()) + " active)",
      t.Ratio(1, 0), "x", "within 5 %");
  }

  // Scaling with the number of active targets.
  {
    report.Text << "\n**Scaling with active targets (ICT face, 1 thread)**\n\n| active targets | "
                   "time per frame | |\n| --- | --- | --- |\n";
    std::cout << "\nScaling with active targets\n";
    for (size_t count : { 1, 2, 4, 8, 16, 32, 53 })
    {
      std::vector<size_t> active;
      for (size_t k = 0; k < count && k < ict.Deltas.size(); ++k)
      {
        active.push_back((k * 13) % ict.Deltas.size());
      }
      const std::vector<double> w = Weights(ict.Deltas.size(), active);
      report.Row(std::to_string(active.size()),
        TimePerCall([&] { KernelBlend(kernel, w, out, 1); }, 0.3) * 1e6, "us");
    }
  }

  // Sparse against dense storage for one target moving a fraction of 100k points: the
  // moved points scattered at random (the worst case for spans), and in runs of 24 points
  // on average, as on the ICT face (its 30-50 % targets; the default face's runs average 34).
  {
    report.Text << "\n**Sparse or dense deltas: one target, 100k points, 1 thread**\n\n"
                << "| moved points | scattered: sparse | in runs: sparse | dense | scattered: "
                   "sparse / dense | in runs: sparse / dense |\n"
                << "| --- | --- | --- | --- | --- | --- |\n";
    std::cout << "\nSparse / dense crossover (scattered, in runs)\n";
    const size_t n = 100000;
    std::vector<float> neutral(n * 3, 0.f), o(n * 3);
    std::mt19937 rng(3);
    const double meanRun = 24.0;
    const auto scattered = [&](double fraction)
    {
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
    const auto inRuns = [&](double fraction)
    {
      std::vector<float> delta(n * 3, 0.f);
      if (fraction >= 1.0)
      {
        std::fill(delta.begin(), delta.end(), 0.001f);
        return delta;
      }
      // Runs and gaps of geometric length: mean run 24, mean gap 24 (1 - f) / f.
      std::geometric_distribution<size_t> run(1.0 / meanRun),
        gap(fraction / (fraction + meanRun * (1.0 - fraction)));
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
    const auto timeBlend = [&](const std::vector<float>& delta, double coverage)
    {
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
            (1.0 - this->PreviousRatio) * (fraction - this->PreviousFraction) /
              (ratio - this->PreviousRatio);
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
      report.Text << "| " << fraction * 100 << " % | " << Format(ts * 1e6) << " us | "
                  << Format(tr * 1e6) << " us | " << Format(td * 1e6) << " us | " << Format(ts / td)
                  << " x | " << Format(tr / td) << " x |\n";
      std::cout << std::left << std::setw(8) << (Format(fraction * 100) + " %") << " scattered "
                << std::setw(8) << Format(ts * 1e6) << " us  in runs " << std::setw(8)
                << Format(tr * 1e6) << " us  dense " << std::setw(8) << Format(td * 1e6) << " us\n";
    }
    const auto crossing = [](const Crossing& c)
    { return c.At < 0 ? std::string("none below 100 %") : "about " + Format(c.At * 100) + " %"; };
    report.Text << "\nCrossover (sparse as fast as dense): scattered " << crossing(crossScattered)
                << ", in runs " << crossing(crossRuns)
                << " of the points moved; MorphMesh::DefaultSparseCoverage = "
                << morphnode::MorphMesh::DefaultSparseCoverage * 100 << " %.\n";
    std::cout << "crossover: scattered " << crossing(crossScattered) << ", in runs "
              << crossing(crossRuns) << "\n";
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
    const double bytes =
      static_cast<double>(big.NumPoints) * 3 * sizeof(float) * (big.Deltas.size() + 2);
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
      0.3, 8,
      [&]
      {
        triad.reset();
        triad = std::make_unique<Triad>(triadBytes);
      });
    const double t1 = t.Time(0), t2 = t.Time(2);
    const double triad1 = triad->Bandwidth(t.Time(1)), triad2 = triad->Bandwidth(t.Time(3));
    // Kernel bandwidth / triad bandwidth = triad time / kernel time * bytes ratio.
    const double share1 = bytes / triad->Bandwidth(1.0) / t.Ratio(0, 1);
    const double share2 = bytes / triad->Bandwidth(1.0) / t.Ratio(2, 3);
    report.Text << "\n**" << big.NumPoints << " points, all " << big.Deltas.size()
                << " targets active, dense**\n\n| measure | value | goal |\n| --- | --- | --- |\n";
    std::cout << "\nMillion-point face\n";
    report.Row("bytes streamed per frame (neutral, " + std::to_string(big.Deltas.size()) +
        " targets, output)",
      bytes / 1e6, "MB");
    report.Row("time per frame, 1 thread", t1 * 1e3, "ms");
    report.Row("time per frame, 2 threads", t2 * 1e3, "ms");
    report.Row("triad bandwidth (3 x " + Format(triadBytes / 1048576.0) + " MiB), 1 thread",
      triad1 / 1e9, "GB/s");
    report.Row("triad bandwidth (3 x " + Format(triadBytes / 1048576.0) + " MiB), 2 threads",
      triad2 / 1e9, "GB/s");
    report.Row("kernel bandwidth / triad bandwidth, 1 thread", share1 * 100, "%");
    report.Row("kernel bandwidth / triad bandwidth, 2 threads", share2 * 100, "%", ">= 75 %");
    report.Goal(std::to_string(big.NumPoints) +
        "-point face, all targets, dense, 2 threads: kernel bandwidth / triad bandwidth",
      share2 * 100, "%", ">= 75 %", share2 >= 0.75);
  }

  // Where the machine's caches end: the triad's bandwidth against its arrays' size.
  {
    report.Text << "\n**Triad bandwidth against array size (2 threads)**\n\n| arrays | working set "
                   "| bandwidth |\n| --- | --- | --- |\n";
    std::cout << "\nTriad bandwidth against array size\n";
    for (size_t mib : { 16, 64, 128, 256 })
    {
      std::unique_ptr<Triad> triad;
      const size_t bytesPerArray = Smoke ? (size_t(1) << 16) : mib << 20;
      const Alternated t({ [&] { triad->Run(2); } }, 0.2, 3,
        [&]
        {
          triad.reset();
          triad = std::make_unique<Triad>(bytesPerArray);
        });
      const double gbs = triad->Bandwidth(t.Time(0)) / 1e9;
      report.Text << "| 3 x " << mib << " MiB | " << 3 * mib << " MiB | " << Format(gbs)
                  << " GB/s |\n";
      std::cout << std::left << std::setw(14) << ("3 x " + std::to_string(mib) + " MiB")
                << Format(gbs) << " GB/s\n";
    }
  }

  headSection();

  // Last, so that the JVM's runs and the 14-geometry scene do not disturb the figures above
  // (the doubling test read 5 % instead of 1-2 % when it ran after them).
  java3dSection();

  WriteMarkdown(markdown, report, loadBefore);
  return 0;
}
