// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar: the running system of Berner (WSCG 2004, Figure 6). An avatar speaks a
// sentence or plays a behaviour script, with idle behaviour (blinks, saccades, head
// micro-motion); the weight optimizer can be switched while it runs, and an overlay shows
// the frame rate, the method, the threshold and the active targets.
//
//   vtkBehaviorTimeSource -> [vtkMorphRigFilter] -> vtkMorphNodeFilter (weights port 1)
//                         -> mapper; HeadYaw/Pitch/Roll -> vtkTransform on the actor
//
// Interactive (a window, time runs in real time):
//   MorphAvatar --say "Hello, how are you?"
//   MorphAvatar --script Data/scripts/greeting.txt
// Offscreen (every frame at the frame rate, to PNG frames and/or a video with sound):
//   MorphAvatar --script Data/scripts/greeting.txt --offscreen --frames out/ --video out/greeting.ogv
// One frame, compared with a baseline (the render regression test):
//   MorphAvatar --script ... --at 1.5 --png frame.png --compare Testing/Baseline/TestMorphAvatar.png
//
// Run `MorphAvatar --help` for every option; docs/avatar.md describes them.
#include "vtkBehaviorTimeSource.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphRigFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInteractorStyleTrackballCamera.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOggTheoraWriter.h"
#include "vtkPNGWriter.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTesting.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkTransform.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLPolyDataWriter.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h> // isatty

namespace
{
using Clock = std::chrono::steady_clock;

//------------------------------------------------------------------------------
/// The morphed face over time as a ParaView time series: FILE.pvd lists FILE/face_*.vtp
/// with their times; each .vtp carries the morph node's arrays and field data and the
/// behaviour's weights (field data `BehaviorWeights`, named by `BehaviorChannels`).
class TimeSeriesWriter
{
public:
  /// Creates the folder beside the .pvd; false (with a message) when it cannot.
  bool Open(const std::string& pvd)
  {
    this->Pvd = pvd;
    const std::string stem = pvd.substr(0, pvd.size() - 4);
    this->Folder = vtksys::SystemTools::GetFilenameName(stem);
    this->FolderPath = stem;
    if (!vtksys::SystemTools::MakeDirectory(stem))
    {
      std::cerr << "MorphAvatar: cannot create the folder " << stem << "\n";
      return false;
    }
    return true;
  }

  bool Write(vtkPolyData* face, vtkTable* weights, double t, int frame)
  {
    vtkNew<vtkPolyData> copy;
    copy->ShallowCopy(face);
    vtkNew<vtkFieldData> fieldData;
    fieldData->ShallowCopy(face->GetFieldData()); // the face's own stays untouched
    copy->SetFieldData(fieldData);
    if (weights)
    {
      vtkNew<vtkDoubleArray> values;
      values->SetName("BehaviorWeights");
      vtkNew<vtkStringArray> channels;
      channels->SetName("BehaviorChannels");
      for (vtkIdType c = 0; c < weights->GetNumberOfColumns(); ++c)
      {
        channels->InsertNextValue(weights->GetColumnName(c));
        values->InsertNextValue(weights->GetValue(0, c).ToDouble());
      }
      fieldData->AddArray(values);
      fieldData->AddArray(channels);
    }
    vtkNew<vtkDoubleArray> time;
    time->SetName("TimeValue");
    time->InsertNextValue(t);
    fieldData->AddArray(time);

    char name[32];
    std::snprintf(name, sizeof(name), "face_%05d.vtp", frame);
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(copy);
    writer->SetFileName((this->FolderPath + "/" + name).c_str());
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    if (writer->Write() != 1)
    {
      std::cerr << "\nMorphAvatar: cannot write " << this->FolderPath << "/" << name << "\n";
      return false;
    }
    this->Entries.emplace_back(t, this->Folder + "/" + name);
    return true;
  }

  bool Close()
  {
    std::ofstream out(this->Pvd);
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <Collection>\n";
    for (const auto& entry : this->Entries)
    {
      out << "    <DataSet timestep=\"" << std::setprecision(9) << entry.first
          << "\" group=\"\" part=\"0\" file=\"" << entry.second << "\"/>\n";
    }
    out << "  </Collection>\n</VTKFile>\n";
    out.close();
    if (!out)
    {
      std::cerr << "MorphAvatar: cannot write " << this->Pvd << "\n";
      return false;
    }
    std::cout << "wrote " << this->Pvd << " (" << this->Entries.size() << " time steps in "
              << this->FolderPath << "/)\n";
    return true;
  }

private:
  std::string Pvd, Folder, FolderPath;
  std::vector<std::pair<double, std::string>> Entries;
};

//------------------------------------------------------------------------------
// Options
struct Options
{
  std::string Face;
  std::string Rig;
  std::string Say;
  std::string Voice = "en";
  std::string Visemes = "paper6";
  std::string Script;
  double Duration = -1.0; // < 0: the script's, else automatic
  double Fps = -1.0;      // < 0: the script's, else 30
  int Width = 640;
  int Height = 640;
  int Method = 3;
  double Threshold = 0.1;
  double MaxError = -1.0; // < 0: 0.5 % of the face's diagonal
  double Hysteresis = 0.0;
  bool SeedSet = false;
  unsigned long long Seed = 1;
  bool Offscreen = false;
  std::string FramesDir;
  std::string Video;
  std::string Pvd; // a ParaView time series: FILE.pvd + FILE/face_*.vtp
  std::string Png;
  std::string Compare;
  double CompareThreshold = 10.0;
  double At = -1.0;
  bool Overlay = true;
  bool Quiet = false;
  double ExitAfter = -1.0; // interactive: close after this many seconds (smoke tests)
  std::string Keys;        // interactive: keys pressed at the start (smoke tests)
};

const char* const MethodNames[] = { "none", "fixed-maximum", "fixed-remaining", "adjusted",
  "error-bounded" };
const char* const MethodLabels[] = { "none (all targets)", "fixed threshold + maximum",
  "fixed threshold + remaining", "adjusted threshold + remaining", "error-bounded" };
constexpr int NumberOfMethods = 5;

void PrintHelp(std::ostream& os)
{
  os << "MorphAvatar: a talking face with morph targets (Berner, WSCG 2004, Figure 6)\n"
        "\n"
        "Usage: MorphAvatar [options]\n"
        "\n"
        "What it says and does:\n"
        "  --say TEXT           speak TEXT (eSpeak NG) at 0.5 s, after the script's speech if\n"
        "                       a script is given; default: a short greeting when no script\n"
        "  --voice en|de|...    eSpeak NG voice of --say and the script (default en)\n"
        "  --visemes SET        viseme set: paper6 (default, A E O S F L), oculus15, german16\n"
        "  --script FILE        a behaviour script (docs/behavior.md), e.g. Data/scripts/greeting.txt\n"
        "  --seed N             seed of the idle behaviour (default 1 or the script's)\n"
        "  --duration S         length in seconds (default: the script's, else the end of the\n"
        "                       last command + 1 s, at least 5 s)\n"
        "  --fps F              frame rate of the track and the offscreen frames (default 30)\n"
        "\n"
        "The face:\n"
        "  --face FILE          a face with morph targets (glTF/GLB, OBJ set); default the\n"
        "                       project's default face (its targets match the channels)\n"
        "  --rig FILE           a rig (docs/rigs.md, e.g. Data/rigs/arkit.json) mapping the\n"
        "                       channels onto the face's own targets\n"
        "\n"
        "The optimizer (keys 0-4 and +/- switch them while it runs):\n"
        "  --method M           0|none, 1|fixed-maximum, 2|fixed-remaining, 3|adjusted\n"
        "                       (default), 4|error-bounded\n"
        "  --threshold T        th_fix of methods 1-3, in [0, 1] (default 0.1)\n"
        "  --max-error E        vertex error bound of method 4 in model units (default 0.5 %\n"
        "                       of the face's bounding-box diagonal)\n"
        "  --hysteresis H       in [0, 0.99): keeps active targets a little longer (default 0)\n"
        "\n"
        "Output:\n"
        "  --size WxH           window / frame size (default 640x640)\n"
        "  --offscreen          no window: render every frame at the frame rate; needs\n"
        "                       --frames, --video, --pvd or --png\n"
        "  --frames DIR         write frame_00000.png ... into DIR (created if missing)\n"
        "  --video FILE         write a video: FILE.ogv (Theora, silent) and FILE.wav; with\n"
        "                       ffmpeg on PATH also FILE.mp4 (or .mkv if FILE ends so) with sound\n"
        "  --pvd FILE.pvd       write the morphed face of every frame as a ParaView time\n"
        "                       series: FILE.pvd and FILE/face_00000.vtp ..., with distance\n"
        "                       arrays (AnimatedRegion, Distance_<target>) and the weights\n"
        "                       (EffectiveWeights, the behaviour's channels) as field data\n"
        "  --at T               render only the frame at time T (with --png / --compare)\n"
        "  --png FILE           write that single frame (default: the last frame)\n"
        "  --compare BASELINE   compare the single frame with a baseline PNG (VTK's image\n"
        "                       comparison); exit code 1 when it differs\n"
        "  --compare-threshold E  largest accepted image error (default 10, VTK's usual)\n"
        "  --no-overlay         no text overlay\n"
        "  --quiet              no progress bar\n"
        "  --exit-after S       interactive: close the window after S seconds and print the\n"
        "                       frame rate and the last overlay (for smoke tests)\n"
        "  --keys KEYS          interactive: press these keys at the start, e.g. '4--'\n"
        "  --help               this text\n"
        "\n"
        "Keys (interactive): 0-4 method, +/- threshold (method 4: error bound), space pause,\n"
        "  r restart, o overlay on/off, q quit; mouse: rotate/zoom the camera.\n";
}

[[noreturn]] void Fail(const std::string& message)
{
  std::cerr << "MorphAvatar: " << message << "\n(see MorphAvatar --help)\n";
  std::exit(2);
}

double ParseNumber(const std::string& option, const std::string& text, double lo, double hi)
{
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
  {
    Fail(option + " expects a number, got '" + text + "'");
  }
  if (v < lo || v > hi)
  {
    std::ostringstream os;
    os << option << " must be in [" << lo << ", " << hi << "], got " << text;
    Fail(os.str());
  }
  return v;
}

int ParseMethod(const std::string& text)
{
  for (int m = 0; m < NumberOfMethods; ++m)
  {
    if (text == MethodNames[m] || text == std::to_string(m))
    {
      return m;
    }
  }
  Fail("--method expects 0-4 or none, fixed-maximum, fixed-remaining, adjusted, "
       "error-bounded; got '" +
    text + "'");
}

Options ParseArguments(int argc, char* argv[])
{
  Options o;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        Fail(arg + " needs a value");
      }
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h")
    {
      PrintHelp(std::cout);
      std::exit(0);
    }
    else if (arg == "--face")
      o.Face = next();
    else if (arg == "--rig")
      o.Rig = next();
    else if (arg == "--say")
    {
      o.Say = next();
      if (o.Say.find_first_not_of(" \t\n") == std::string::npos)
      {
        Fail("--say needs a non-empty text");
      }
    }
    else if (arg == "--voice")
      o.Voice = next();
    else if (arg == "--visemes")
      o.Visemes = next();
    else if (arg == "--script")
      o.Script = next();
    else if (arg == "--seed")
    {
      const std::string s = next();
      char* end = nullptr;
      o.Seed = std::strtoull(s.c_str(), &end, 10);
      if (s.empty() || *end != '\0' || s[0] == '-')
      {
        Fail("--seed expects an unsigned integer, got '" + s + "'");
      }
      o.SeedSet = true;
    }
    else if (arg == "--duration")
      o.Duration = ParseNumber(arg, next(), 0.0, 24 * 3600.0);
    else if (arg == "--fps")
      o.Fps = ParseNumber(arg, next(), 1.0, 240.0);
    else if (arg == "--size")
    {
      const std::string s = next();
      int w = 0, h = 0;
      char tail = 0;
      if (std::sscanf(s.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 16 || h < 16 ||
        w > 8192 || h > 8192)
      {
        Fail("--size expects WxH with 16 <= W, H <= 8192, e.g. 640x480; got '" + s + "'");
      }
      o.Width = w;
      o.Height = h;
    }
    else if (arg == "--method")
      o.Method = ParseMethod(next());
    else if (arg == "--threshold")
      o.Threshold = ParseNumber(arg, next(), 0.0, 1.0);
    else if (arg == "--max-error")
      o.MaxError = ParseNumber(arg, next(), 0.0, 1e30);
    else if (arg == "--hysteresis")
      o.Hysteresis = ParseNumber(arg, next(), 0.0, 0.99);
    else if (arg == "--offscreen")
      o.Offscreen = true;
    else if (arg == "--frames")
      o.FramesDir = next();
    else if (arg == "--video")
      o.Video = next();
    else if (arg == "--pvd")
      o.Pvd = next();
    else if (arg == "--png")
      o.Png = next();
    else if (arg == "--compare")
      o.Compare = next();
    else if (arg == "--compare-threshold")
      o.CompareThreshold = ParseNumber(arg, next(), 0.0, 1000.0);
    else if (arg == "--at")
      o.At = ParseNumber(arg, next(), 0.0, 24 * 3600.0);
    else if (arg == "--exit-after")
      o.ExitAfter = ParseNumber(arg, next(), 0.0, 1e6);
    else if (arg == "--keys")
      o.Keys = next();
    else if (arg == "--no-overlay")
      o.Overlay = false;
    else if (arg == "--quiet")
      o.Quiet = true;
    else
    {
      Fail("unknown argument '" + arg + "'");
    }
  }
  if (o.Say.empty() && o.Script.empty())
  {
    o.Say = o.Voice.rfind("de", 0) == 0 ? "Hallo! Ich bin ein Avatar mit Morph-Targets."
                                        : "Hello! I am an avatar made of morph targets.";
  }
  if (!o.Script.empty() && !vtksys::SystemTools::FileExists(o.Script, true))
  {
    Fail("no script file '" + o.Script + "'");
  }
  if (!o.Face.empty() && !vtksys::SystemTools::FileExists(o.Face))
  {
    Fail("no face '" + o.Face + "'");
  }
  if (!o.Rig.empty() && !vtksys::SystemTools::FileExists(o.Rig, true))
  {
    Fail("no rig file '" + o.Rig + "'");
  }
  if (!o.Compare.empty() && !vtksys::SystemTools::FileExists(o.Compare, true))
  {
    Fail("no baseline '" + o.Compare + "'");
  }
  if (!o.FramesDir.empty() || !o.Video.empty() || !o.Pvd.empty() || !o.Png.empty() ||
    !o.Compare.empty() || o.At >= 0.0)
  {
    o.Offscreen = true; // writing files means rendering every frame offscreen
  }
  if (o.Offscreen && o.FramesDir.empty() && o.Video.empty() && o.Pvd.empty() &&
    o.Png.empty() && o.Compare.empty())
  {
    Fail("--offscreen needs somewhere to write: --frames DIR, --video FILE, --pvd FILE or "
         "--png FILE");
  }
  if (o.At >= 0.0 && (!o.FramesDir.empty() || !o.Video.empty() || !o.Pvd.empty()))
  {
    Fail("--at renders one frame (for --png / --compare); leave out --frames, --video and --pvd");
  }
  if (!o.Pvd.empty() &&
    vtksys::SystemTools::LowerCase(vtksys::SystemTools::GetFilenameLastExtension(o.Pvd)) != ".pvd")
  {
    Fail("--pvd takes a file name ending in .pvd, not '" + o.Pvd + "'");
  }
  return o;
}

//------------------------------------------------------------------------------
// The scene and its state
struct Avatar
{
  Options Opt;
  vtkNew<vtkBehaviorTimeSource> Behavior;
  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphRigFilter> Rig;
  vtkNew<vtkMorphNodeFilter> Morph;
  vtkNew<vtkPolyData> Display;
  vtkNew<vtkPolyDataMapper> Mapper;
  vtkNew<vtkActor> Actor;
  vtkNew<vtkTransform> HeadPose;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkTextActor> Overlay;
  vtkNew<vtkTextActor> Caption;
  double Pivot[3] = { 0, 0, 0 };
  double Diagonal = 1.0;
  double Duration = 5.0;
  double Fps = 30.0;
  int Method = 3;
  double Threshold = 0.1;
  double MaxError = 0.0;
  double Time = 0.0;
  std::string Sentence;

  // Interactive clock
  bool Paused = false;
  Clock::time_point Start;
  double StartTime = 0.0;
  double MeasuredFps = 0.0;
  int FramesSinceMeasure = 0;
  int FramesRendered = 0;
  Clock::time_point Launched;
  Clock::time_point MeasureStart;

  void ApplyMethod()
  {
    vtkMorphNodeFilter* m = this->Morph;
    m->SetThreshold(0.0);
    m->SetAdjustThreshold(false);
    m->SetMaxVertexError(0.0);
    m->SetRedistributionStrategyToRemaining();
    switch (this->Method)
    {
      case 1:
        m->SetThreshold(this->Threshold);
        m->SetRedistributionStrategyToMaximum();
        break;
      case 2:
        m->SetThreshold(this->Threshold);
        break;
      case 3:
        m->SetThreshold(this->Threshold);
        m->SetAdjustThreshold(true);
        break;
      case 4:
        m->SetMaxVertexError(this->MaxError);
        break;
      default:
        break;
    }
    m->ResetHysteresis();
  }

  double Channel(vtkTable* table, const char* name)
  {
    vtkAbstractArray* column = table ? table->GetColumnByName(name) : nullptr;
    auto* data = vtkArrayDownCast<vtkDataArray>(column);
    return data && data->GetNumberOfTuples() > 0 ? data->GetTuple1(0) : 0.0;
  }

  /// Brings the face to time t: weights, blend, head pose, overlay. False on error.
  bool Update(double t)
  {
    this->Time = t;
    if (!this->Morph->UpdateTimeStep(t))
    {
      return false;
    }
    auto* face = vtkPolyData::SafeDownCast(this->Morph->GetOutput());
    if (!face || face->GetNumberOfPoints() == 0)
    {
      return false;
    }
    this->Display->ShallowCopy(face);
    auto* weights = vtkTable::SafeDownCast(this->Behavior->GetOutputDataObject(0));
    // Angles seen from the character (docs/behavior.md): yaw > 0 turns to its left (+X,
    // the face looks along +Z), pitch > 0 up, roll > 0 tilts the crown to its left.
    this->HeadPose->Identity();
    this->HeadPose->Translate(this->Pivot);
    this->HeadPose->RotateY(this->Channel(weights, "HeadYaw"));
    this->HeadPose->RotateX(-this->Channel(weights, "HeadPitch"));
    this->HeadPose->RotateZ(-this->Channel(weights, "HeadRoll"));
    this->HeadPose->Translate(-this->Pivot[0], -this->Pivot[1], -this->Pivot[2]);
    return true;
  }

  std::string OverlayText(bool offscreen, int frame, int frames)
  {
    std::ostringstream os;
    os << std::fixed;
    if (offscreen)
    {
      os << std::setprecision(1) << this->Fps << " fps   frame " << frame << " / " << frames;
    }
    else
    {
      os << std::setprecision(1) << this->MeasuredFps << " fps" << (this->Paused ? "   (paused)" : "");
    }
    os << "\nmethod " << this->Method << ": " << MethodLabels[this->Method] << "\n";
    if (this->Method >= 1 && this->Method <= 3)
    {
      os << "threshold " << std::setprecision(3) << this->Threshold << "\n";
    }
    else if (this->Method == 4)
    {
      os << "max vertex error " << std::setprecision(2) << 100.0 * this->MaxError / this->Diagonal
         << " % of the face\n";
    }
    else
    {
      os << "threshold -\n";
    }
    const int targets = std::max(0, this->Morph->GetNumberOfTargets() - 1);
    os << "active targets " << this->Morph->GetActiveTargetCount() << " / " << targets
       << "   error bound " << std::setprecision(2)
       << 100.0 * this->Morph->GetErrorBound() / this->Diagonal << " %\n";
    os << "t = " << std::setprecision(2) << this->Time << " s / " << this->Duration << " s";
    if (!offscreen)
    {
      os << "\nkeys: 0-4 method  +/- threshold  space pause  r restart  q quit";
    }
    return os.str();
  }
};

//------------------------------------------------------------------------------
// The interactive mode: keys and the real-time clock
class AvatarStyle : public vtkInteractorStyleTrackballCamera
{
public:
  static AvatarStyle* New();
  vtkTypeMacro(AvatarStyle, vtkInteractorStyleTrackballCamera);
  Avatar* Scene = nullptr;

  void OnChar() override
  {
    // Our keys must not reach the default handling ('3' is stereo, 'r' resets the camera).
    const char key = this->Interactor->GetKeyCode();
    if (std::string("01234+-=r o").find(key) != std::string::npos && key != '\0')
    {
      return;
    }
    this->Superclass::OnChar();
  }

  void OnKeyPress() override
  {
    Avatar& a = *this->Scene;
    const std::string sym = this->Interactor->GetKeySym() ? this->Interactor->GetKeySym() : "";
    const char key = this->Interactor->GetKeyCode();
    if (key >= '0' && key <= '4')
    {
      a.Method = key - '0';
    }
    else if (key == '+' || key == '=' || sym == "plus" || sym == "KP_Add" || sym == "equal")
    {
      if (a.Method == 4)
        a.MaxError *= 1.25;
      else
        a.Threshold = std::min(1.0, a.Threshold + 0.025);
    }
    else if (key == '-' || sym == "minus" || sym == "KP_Subtract")
    {
      if (a.Method == 4)
        a.MaxError /= 1.25;
      else
        a.Threshold = std::max(0.0, a.Threshold - 0.025);
    }
    else if (key == ' ' || sym == "space")
    {
      const double now = a.Time;
      a.Paused = !a.Paused;
      a.Start = Clock::now();
      a.StartTime = now;
    }
    else if (key == 'r')
    {
      a.Start = Clock::now();
      a.StartTime = 0.0;
    }
    else if (key == 'o')
    {
      a.Overlay->SetVisibility(!a.Overlay->GetVisibility());
    }
    else
    {
      this->Superclass::OnKeyPress();
      return;
    }
    a.ApplyMethod();
  }
};
vtkStandardNewMacro(AvatarStyle);

void OnTimer(vtkObject* caller, unsigned long, void* clientData, void*)
{
  auto* a = static_cast<Avatar*>(clientData);
  auto* interactor = static_cast<vtkRenderWindowInteractor*>(caller);
  const auto now = Clock::now();
  double t = a->StartTime;
  if (!a->Paused)
  {
    t += std::chrono::duration<double>(now - a->Start).count();
    if (t > a->Duration) // loop
    {
      a->Start = now;
      a->StartTime = 0.0;
      a->Morph->ResetHysteresis();
      t = 0.0;
    }
  }
  a->Update(t);
  ++a->FramesSinceMeasure;
  const double since = std::chrono::duration<double>(now - a->MeasureStart).count();
  if (since >= 0.5)
  {
    a->MeasuredFps = a->FramesSinceMeasure / since;
    a->FramesSinceMeasure = 0;
    a->MeasureStart = now;
  }
  a->Overlay->SetInput(a->OverlayText(false, 0, 0).c_str());
  interactor->Render();
  ++a->FramesRendered;
  if (a->Opt.ExitAfter >= 0.0 &&
    std::chrono::duration<double>(now - a->Launched).count() >= a->Opt.ExitAfter)
  {
    const double seconds = std::chrono::duration<double>(Clock::now() - a->Launched).count();
    std::cout << "rendered " << a->FramesRendered << " frames in " << std::fixed
              << std::setprecision(2) << seconds << " s (" << std::setprecision(1)
              << a->FramesRendered / seconds << " fps)\n"
              << a->Overlay->GetInput() << "\n";
    interactor->TerminateApp();
  }
}

//------------------------------------------------------------------------------
// Offscreen helpers
class ProgressBar
{
public:
  ProgressBar(int total, bool enabled)
    : Total(total)
    , Enabled(enabled)
    , Tty(isatty(fileno(stderr)) != 0)
    , Begin(Clock::now())
  {
  }
  void Show(int done)
  {
    if (!this->Enabled)
    {
      return;
    }
    const auto now = Clock::now();
    const bool last = done >= this->Total;
    // In place on a terminal (at most 20 updates a second); in a log every 10 %.
    if (this->Tty && !last && now - this->LastShown < std::chrono::milliseconds(50))
    {
      return;
    }
    const int percent = this->Total > 0 ? static_cast<int>(100.0 * done / this->Total) : 100;
    if (!this->Tty && !last && percent / 10 == this->LastDecile)
    {
      return;
    }
    this->LastDecile = percent / 10;
    this->LastShown = now;
    const double elapsed = std::chrono::duration<double>(now - this->Begin).count();
    const double eta = done > 0 ? elapsed * (this->Total - done) / done : 0.0;
    const int width = 30;
    const int filled = this->Total > 0 ? width * done / this->Total : width;
    std::ostringstream os;
    os << (this->Tty ? "\r[" : "[") << std::string(filled, '#') << std::string(width - filled, '.') << "] "
       << std::setw(3) << percent << "%  " << done << "/" << this->Total << " frames  "
       << (last ? "done in " : "ETA ") << std::fixed << std::setprecision(1)
       << (last ? elapsed : eta) << " s   ";
    std::cerr << os.str() << (this->Tty && !last ? "" : "\n") << std::flush;
  }

private:
  int Total;
  bool Enabled;
  bool Tty;
  Clock::time_point Begin;
  Clock::time_point LastShown;
  int LastDecile = -1;
};

bool HasProgram(const std::string& name)
{
  const std::string command = "command -v " + name + " >/dev/null 2>&1";
  return std::system(command.c_str()) == 0;
}

std::string Quote(const std::string& s)
{
  std::string q = "'";
  for (char c : s)
  {
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return q + "'";
}

bool WritePng(vtkRenderWindow* window, const std::string& file)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  return writer->GetErrorCode() == 0;
}

int RunOffscreen(Avatar& a)
{
  const Options& o = a.Opt;
  vtkRenderWindow* window = a.Window;

  // One frame: --at (or the last frame) to --png and/or compared with --compare.
  if (o.At >= 0.0 || (o.FramesDir.empty() && o.Video.empty() && o.Pvd.empty()))
  {
    const double t = o.At >= 0.0 ? o.At : a.Duration;
    const int frame = static_cast<int>(std::floor(t * a.Fps + 1e-9));
    const int frames = static_cast<int>(std::floor(a.Duration * a.Fps + 1e-9)) + 1;
    if (!a.Update(t))
    {
      std::cerr << "MorphAvatar: the face could not be morphed (see the errors above)\n";
      return 1;
    }
    a.Overlay->SetInput(a.OverlayText(true, frame, frames).c_str());
    window->Render();
    if (!o.Png.empty())
    {
      if (!WritePng(window, o.Png))
      {
        std::cerr << "MorphAvatar: cannot write " << o.Png << "\n";
        return 1;
      }
      std::cout << "wrote " << o.Png << " (t = " << t << " s)\n";
    }
    if (!o.Compare.empty())
    {
      const std::string outDir = o.Png.empty()
        ? vtksys::SystemTools::GetCurrentWorkingDirectory()
        : vtksys::SystemTools::GetFilenamePath(vtksys::SystemTools::CollapseFullPath(o.Png));
      vtkNew<vtkTesting> testing;
      testing->AddArgument("-V");
      const std::string baseline = vtksys::SystemTools::CollapseFullPath(o.Compare);
      testing->AddArgument(baseline.c_str());
      testing->AddArgument("-T");
      testing->AddArgument(outDir.c_str());
      testing->SetRenderWindow(window);
      const int result = testing->RegressionTest(o.CompareThreshold);
      if (result != vtkTesting::PASSED)
      {
        std::cerr << "MorphAvatar: the frame differs from " << o.Compare << " (images in "
                  << outDir << ")\n";
        return 1;
      }
      std::cout << "the frame matches " << o.Compare << "\n";
    }
    return 0;
  }

  // Every frame at the frame rate.
  const int frames = static_cast<int>(std::floor(a.Duration * a.Fps + 1e-9)) + 1;
  if (!o.FramesDir.empty() && !vtksys::SystemTools::MakeDirectory(o.FramesDir))
  {
    std::cerr << "MorphAvatar: cannot create the folder " << o.FramesDir << "\n";
    return 1;
  }
  std::string ogv, wav, muxed;
  if (!o.Video.empty())
  {
    const std::string dir = vtksys::SystemTools::GetFilenamePath(o.Video);
    if (!dir.empty() && !vtksys::SystemTools::MakeDirectory(dir))
    {
      std::cerr << "MorphAvatar: cannot create the folder " << dir << "\n";
      return 1;
    }
    std::string ext = vtksys::SystemTools::LowerCase(
      vtksys::SystemTools::GetFilenameLastExtension(o.Video));
    const std::string stem = ext.empty() ? o.Video
                                         : o.Video.substr(0, o.Video.size() - ext.size());
    ogv = stem + ".ogv";
    wav = stem + ".wav";
    muxed = stem + (ext == ".mkv" ? ".mkv" : ".mp4");
  }

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  vtkNew<vtkPNGWriter> png;
  png->SetInputConnection(grab->GetOutputPort());
  vtkNew<vtkOggTheoraWriter> video;
  if (!ogv.empty())
  {
    video->SetInputConnection(grab->GetOutputPort());
    video->SetFileName(ogv.c_str());
    video->SetRate(std::max(1, static_cast<int>(std::lround(a.Fps))));
    video->SetQuality(2);
  }

  TimeSeriesWriter series;
  if (!o.Pvd.empty() && !series.Open(o.Pvd))
  {
    return 1;
  }

  ProgressBar progress(frames, !o.Quiet);
  bool videoStarted = false;
  for (int f = 0; f < frames; ++f)
  {
    const double t = f / a.Fps;
    if (!a.Update(t))
    {
      std::cerr << "\nMorphAvatar: the face could not be morphed at t = " << t
                << " (see the errors above)\n";
      return 1;
    }
    if (!o.Pvd.empty() &&
      !series.Write(vtkPolyData::SafeDownCast(a.Morph->GetOutput()),
        vtkTable::SafeDownCast(a.Behavior->GetOutputDataObject(0)), t, f))
    {
      return 1;
    }
    a.Overlay->SetInput(a.OverlayText(true, f, frames).c_str());
    window->Render();
    grab->Modified();
    if (!o.FramesDir.empty())
    {
      char name[32];
      std::snprintf(name, sizeof(name), "/frame_%05d.png", f);
      png->SetFileName((o.FramesDir + name).c_str());
      png->Write();
      if (png->GetErrorCode() != 0)
      {
        std::cerr << "\nMorphAvatar: cannot write " << o.FramesDir << name << "\n";
        return 1;
      }
    }
    if (!ogv.empty())
    {
      if (!videoStarted)
      {
        grab->Update();
        video->Start();
        videoStarted = true;
      }
      video->Write();
      if (video->GetError())
      {
        std::cerr << "\nMorphAvatar: cannot write the video " << ogv << "\n";
        return 1;
      }
    }
    progress.Show(f + 1);
  }
  if (videoStarted)
  {
    video->End();
  }
  if (!o.Pvd.empty() && !series.Close())
  {
    return 1;
  }
  if (!o.FramesDir.empty())
  {
    std::cout << "wrote " << frames << " frames to " << o.FramesDir << "/frame_*.png at "
              << a.Fps << " fps\n";
  }
  if (!ogv.empty())
  {
    std::cout << "wrote " << ogv << " (silent)\n";
    if (!a.Behavior->WriteAudio(wav.c_str()))
    {
      std::cerr << "MorphAvatar: cannot write the audio " << wav << "\n";
      return 1;
    }
    std::cout << "wrote " << wav << "\n";
    if (HasProgram("ffmpeg"))
    {
      const std::string command = "ffmpeg -y -loglevel error -i " + Quote(ogv) + " -i " +
        Quote(wav) + " -c:v libx264 -pix_fmt yuv420p -c:a aac -b:a 128k -shortest " +
        Quote(muxed);
      if (std::system(command.c_str()) != 0)
      {
        std::cerr << "MorphAvatar: ffmpeg could not mux " << muxed << " (kept " << ogv
                  << " and " << wav << ")\n";
        return 1;
      }
      std::cout << "wrote " << muxed << " (video with sound)\n";
    }
    else
    {
      std::cout << "ffmpeg is not on PATH: no video with sound; kept the silent " << ogv
                << " and " << wav << " (mux them with: ffmpeg -i " << Quote(ogv) << " -i "
                << Quote(wav) << " -c:v libx264 -pix_fmt yuv420p -c:a aac " << Quote(muxed)
                << ")\n";
    }
  }
  return 0;
}

/// The first polydata of the reader's output (a composite dataset or a polydata).
vtkPolyData* FirstPolyData(vtkDataObject* data)
{
  if (auto* poly = vtkPolyData::SafeDownCast(data))
  {
    return poly;
  }
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      if (auto* poly = vtkPolyData::SafeDownCast(it->GetCurrentDataObject()))
      {
        return poly;
      }
    }
  }
  return nullptr;
}
} // namespace

int main(int argc, char* argv[])
{
  Avatar a;
  a.Opt = ParseArguments(argc, argv);
  Options& o = a.Opt;

  if (!std::getenv("DISPLAY"))
  {
    std::cerr << "MorphAvatar: no X display (DISPLAY is not set). VTK renders through X, "
                 "offscreen too: run under `xvfb-run -a MorphAvatar ...`.\n";
    return 2;
  }

  // --- the behaviour ---------------------------------------------------------
  vtkBehaviorTimeSource* behavior = a.Behavior;
  behavior->SetVoice(o.Voice.c_str());
  if (!behavior->SetVisemeSetFromString(o.Visemes.c_str()))
  {
    Fail("--visemes expects paper6, oculus15 or german16; got '" + o.Visemes + "'");
  }
  if (!o.Script.empty() && !behavior->LoadScript(o.Script.c_str()))
  {
    std::cerr << "MorphAvatar: cannot load the script " << o.Script << " (see above)\n";
    return 1;
  }
  if (!o.Say.empty() && !behavior->Say(o.Say.c_str(), o.Script.empty() ? 0.5 : -1.0))
  {
    std::cerr << "MorphAvatar: cannot say '" << o.Say << "' with voice '" << o.Voice
              << "' (see above; `espeak-ng --voices` lists the voices)\n";
    return 1;
  }
  if (o.SeedSet)
    behavior->SetSeed(o.Seed);
  if (o.Fps > 0.0)
    behavior->SetFrameRate(o.Fps);
  if (o.Duration >= 0.0)
    behavior->SetDuration(o.Duration);
  a.Fps = behavior->GetFrameRate();
  a.Duration = behavior->GetEffectiveDuration();
  a.Sentence = o.Say;

  // --- the face ----------------------------------------------------------------
  const std::string face =
    o.Face.empty() ? std::string(MORPHNODE_DATA_DIR) + "/DefaultFace/default_face.glb" : o.Face;
  a.Reader->SetFileName(face.c_str());
  a.Morph->SetInputConnection(a.Reader->GetOutputPort());
  // The behaviour's channels are glTF-style weights: each adds its target's deltas, so a
  // blink does not weaken a vowel (RELATIVE mode).
  a.Morph->SetWeightModeToRelative();
  a.Morph->SetHysteresis(o.Hysteresis);
  // For ParaView: colour by AnimatedRegion or Distance_<target>.
  a.Morph->SetGenerateDistanceArrays(!o.Pvd.empty());
  if (!o.Rig.empty())
  {
    a.Rig->SetRigFileName(o.Rig.c_str());
    a.Rig->SetInputConnection(behavior->GetOutputPort(0));
    a.Rig->SetFaceConnection(a.Reader->GetOutputPort());
    a.Morph->SetWeightsConnection(a.Rig->GetOutputPort());
  }
  else
  {
    a.Morph->SetWeightsConnection(behavior->GetOutputPort(0));
  }
  a.Reader->Update();
  vtkPolyData* neutral = FirstPolyData(a.Reader->GetOutputDataObject(0));
  if (!neutral || neutral->GetNumberOfPoints() == 0)
  {
    std::cerr << "MorphAvatar: cannot read a face from " << face << " (see above)\n";
    return 1;
  }
  if (!a.Update(0.0))
  {
    std::cerr << "MorphAvatar: the face could not be morphed (see the errors above)\n";
    return 1;
  }
  if (o.Rig.empty())
  {
    // Without a rig the channels must name the face's targets.
    int matched = 0;
    for (int c = 0; c < behavior->GetNumberOfChannels(); ++c)
    {
      matched += a.Morph->GetTargetIndex(behavior->GetChannelName(c)) >= 0 ? 1 : 0;
    }
    if (matched == 0)
    {
      std::cerr << "MorphAvatar: no behaviour channel names a target of " << face
                << "; give a rig with --rig (e.g. Data/rigs/arkit.json)\n";
      return 1;
    }
  }
  double bounds[6];
  neutral->GetBounds(bounds);
  a.Diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  if (!(a.Diagonal > 0.0))
    a.Diagonal = 1.0;
  // The head turns about the top of the neck: centred, a quarter up from the chin.
  a.Pivot[0] = 0.5 * (bounds[0] + bounds[1]);
  a.Pivot[1] = bounds[2] + 0.25 * (bounds[3] - bounds[2]);
  a.Pivot[2] = 0.5 * (bounds[4] + bounds[5]);
  a.Method = o.Method;
  a.Threshold = o.Threshold;
  a.MaxError = o.MaxError >= 0.0 ? o.MaxError : 0.005 * a.Diagonal;
  a.ApplyMethod();
  a.Update(0.0);

  // --- the scene ---------------------------------------------------------------
  a.Mapper->SetInputData(a.Display);
  a.Mapper->ScalarVisibilityOff();
  a.Actor->SetMapper(a.Mapper);
  a.Actor->SetUserTransform(a.HeadPose);
  a.Actor->GetProperty()->SetColor(0.86, 0.72, 0.62);
  a.Actor->GetProperty()->SetSpecular(0.2);
  a.Actor->GetProperty()->SetSpecularPower(20);
  a.Renderer->SetBackground(0.15, 0.16, 0.2);
  a.Renderer->SetBackground2(0.32, 0.34, 0.42);
  a.Renderer->GradientBackgroundOn();
  a.Renderer->AddActor(a.Actor);

  vtkTextProperty* text = a.Overlay->GetTextProperty();
  text->SetFontFamilyToCourier();
  text->SetFontSize(std::max(10, o.Height / 40));
  text->SetColor(0.95, 0.95, 0.85);
  text->SetBackgroundColor(0.0, 0.0, 0.0);
  text->SetBackgroundOpacity(0.45);
  text->SetVerticalJustificationToTop();
  a.Overlay->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  a.Overlay->SetPosition(0.012, 0.988);
  a.Overlay->SetVisibility(o.Overlay);
  a.Renderer->AddActor2D(a.Overlay);

  // The sentence (or the script's name) at the bottom, like the paper's sentence choice.
  std::string caption = !o.Script.empty() ? vtksys::SystemTools::GetFilenameName(o.Script) : "";
  if (!o.Say.empty())
  {
    caption += (caption.empty() ? "\"" : " + \"") + o.Say + "\"";
  }
  a.Caption->SetInput(caption.c_str());
  vtkTextProperty* captionText = a.Caption->GetTextProperty();
  captionText->SetFontSize(std::max(10, o.Height / 36));
  captionText->SetColor(1.0, 1.0, 1.0);
  captionText->SetJustificationToCentered();
  captionText->SetItalic(true);
  a.Caption->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  a.Caption->SetPosition(0.5, 0.02);
  a.Caption->SetVisibility(o.Overlay);
  a.Renderer->AddActor2D(a.Caption);

  a.Window->SetSize(o.Width, o.Height);
  a.Window->SetMultiSamples(0);
  a.Window->AddRenderer(a.Renderer);
  a.Window->SetWindowName("MorphAvatar");
  a.Renderer->ResetCamera(bounds);
  a.Renderer->GetActiveCamera()->Zoom(1.3);
  a.Renderer->ResetCameraClippingRange(bounds[0] - a.Diagonal, bounds[1] + a.Diagonal,
    bounds[2] - a.Diagonal, bounds[3] + a.Diagonal, bounds[4] - a.Diagonal,
    bounds[5] + a.Diagonal);

  if (!o.Quiet)
  {
    std::cout << face << ": " << a.Morph->GetNumberOfTargets() << " targets; behaviour "
              << a.Duration << " s at " << a.Fps << " fps, " << behavior->GetNumberOfChannels()
              << " channels, " << behavior->GetNumberOfUtterances() << " utterance(s)\n";
  }

  if (o.Offscreen)
  {
    a.Window->OffScreenRenderingOn();
    return RunOffscreen(a);
  }

  // --- interactive -------------------------------------------------------------
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(a.Window);
  vtkNew<AvatarStyle> style;
  style->Scene = &a;
  interactor->SetInteractorStyle(style);
  interactor->Initialize();
  vtkNew<vtkCallbackCommand> timer;
  timer->SetCallback(OnTimer);
  timer->SetClientData(&a);
  interactor->AddObserver(vtkCommand::TimerEvent, timer);
  interactor->CreateRepeatingTimer(5);
  for (char key : o.Keys)
  {
    const char sym[2] = { key, '\0' };
    interactor->SetKeyEventInformation(0, 0, key, 1, key == '+' ? "plus" : key == '-' ? "minus" : sym);
    interactor->InvokeEvent(vtkCommand::KeyPressEvent);
    interactor->InvokeEvent(vtkCommand::CharEvent);
  }
  a.Start = a.MeasureStart = a.Launched = Clock::now();
  a.Window->Render();
  interactor->Start();
  return 0;
}
