// SPDX-License-Identifier: BSD-3-Clause
// LipGapStudy: do the lips close at p, b and m after the optimizer? The long text spoken by
// eSpeak NG onto every face (the default face with its own targets, the ICT head through the
// ARKit rig, the MakeHuman avatar through the Ready Player Me rig), the lip gap (the midline
// vertices of the upper and lower lip that touch at rest, LipGapStudy.h) at every frame for
// every optimizer method, deciding per face target (the optimizer on the rig's expansion, as
// before) and per rig shape (rig/RigOptimizer.h). Writes summary.md / .csv, bilabials.csv, a
// plot of the ICT head's lip gap over time and a contact sheet of p/b/m and o before and after
// (docs/optimizer-study.md).
#include "LipGapStudy.h"

#include "CommandLine.h"
#include "DataPaths.h"
#include "HeadActors.h"
#include "ImageOutput.h"

#include "base/Text.h"

#include "vtkAxis.h"
#include "vtkCamera.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkFloatArray.h"
#include "vtkImageAppend.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWindowToImageFilter.h"

#include <fstream>
#include <iomanip>
#include <iostream>

using namespace morphnode_lips;
namespace appkit = morphnode::appkit;

namespace
{
struct Row
{
  std::string Face, Method, Decision;
  int Bilabials = 0, Open = 0;
  double MeanGap = 0.0, WorstGap = 0.0; ///< at the bilabials, mm above the rest gap
  double OverOpen = 0.0;                ///< mm, the most the lips open beyond unoptimized
};

/// Renders the face's mouth with the given relative target weights (the face's targets).
vtkSmartPointer<vtkImageData> RenderMouth(
  const StudyFace& face, const std::vector<double>& weights, const std::string& label, int size)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(face.Spec.File.c_str());
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative();
  for (size_t t = 0; t < face.Targets.size(); ++t)
  {
    if (weights[t] != 0.0)
    {
      morph->SetWeightByName(face.Targets[t].c_str(), weights[t]);
    }
  }
  morph->Update();
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(size, size);
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  appkit::HeadActors actors;
  actors.Build(morph->GetOutputDataObject(0), renderer, nullptr);
  const auto& points = face.Scene.Parts[face.LipPart].Positions;
  double lip[3] = { points[3 * face.Lips.Upper], points[3 * face.Lips.Upper + 1],
    points[3 * face.Lips.Upper + 2] };
  const double half = 0.035 * 1000.0 / face.Spec.MillimetresPerUnit; // 7 cm across
  const double bounds[6] = { lip[0] - half, lip[0] + half, lip[1] - half, lip[1] + half,
    lip[2] - 0.5 * half, lip[2] };
  appkit::HeadActors::SetUpView(renderer, bounds);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(lip);
  camera->SetPosition(lip[0], lip[1], lip[2] + 12.0 * half);
  camera->SetViewUp(0, 1, 0);
  camera->SetViewAngle(18.0);
  renderer->ResetCameraClippingRange();
  vtkNew<vtkTextActor> text;
  text->SetInput(label.c_str());
  text->GetTextProperty()->SetFontSize(size / 18);
  text->GetTextProperty()->SetColor(1, 1, 1);
  text->GetTextProperty()->SetBackgroundColor(0, 0, 0);
  text->GetTextProperty()->SetBackgroundOpacity(0.5);
  text->SetPosition(4, 4);
  renderer->AddActor2D(text);
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->Update();
  vtkSmartPointer<vtkImageData> image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

/// Relative target weights of one frame of the track, decided as asked.
std::vector<double> FrameWeights(const StudyFace& face, const WeightTrack& visemes, size_t frame,
  const OptimizerSettings& s, Decide decide)
{
  // The decisions carry hysteresis; the presets here have none, so one frame alone decides
  // as in the run.
  WeightTrack one(visemes.GetChannels(), visemes.GetFrameRate());
  one.AppendFrame(visemes.GetFrame(frame));
  const Rig& rig = face.Shapes;
  std::vector<double> shapes(rig.GetNumberOfShapes(), 0.0), effective(shapes.size());
  for (size_t c = 0; c < visemes.GetNumberOfChannels(); ++c)
  {
    const int k = rig.FindShape(visemes.GetChannels()[c]);
    if (k >= 0)
    {
      shapes[static_cast<size_t>(k)] += visemes.GetValue(frame, c);
    }
  }
  std::vector<double> targets(face.Targets.size());
  if (decide == Decide::PerShape)
  {
    RigOptimizer o;
    o.SetSettings(s);
    o.SetShapeDistances(face.ShapeFigures);
    o.Optimize(shapes.data(), effective.data());
    rig.Expand(effective.data(), targets.data());
    return targets;
  }
  rig.Expand(shapes.data(), targets.data());
  if (s.IsActive())
  {
    std::vector<double> absolute(targets.size() + 1);
    double sum = 0.0;
    for (size_t t = 0; t < targets.size(); ++t)
    {
      absolute[t + 1] = targets[t];
      sum += targets[t];
    }
    absolute[0] = 1.0 - sum;
    WeightOptimizer o;
    o.SetSettings(s);
    o.SetTargetDistances(face.TargetFigures);
    const auto e = o.Optimize(absolute);
    std::copy(e.begin() + 1, e.end(), targets.begin());
  }
  return targets;
}
} // namespace

int main(int argc, char* argv[])
{
  std::string out = "lip-study";
  std::string textFile = appkit::DataPath("scripts/long-text.txt");
  double threshold = 0.1;
  double plotFrom = 0.0, plotTo = 4.0;
  CLI::App app("LipGapStudy: the lip gap at every bilabial (p, b, m) of a long text, per "
               "optimizer method, deciding per face target or per rig shape, on the default "
               "face, the ICT head and the MakeHuman avatar (docs/optimizer-study.md)");
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--text", textFile, "the text to speak")
    ->default_str("Data/scripts/long-text.txt");
  appkit::AddNumberOption(
    app, "--threshold", threshold, 0.0, 1.0, "th_fix of the threshold methods");
  appkit::AddNumberOption(app, "--plot-from", plotFrom, 0.0, 1e6, "plot window start (s)");
  appkit::AddNumberOption(app, "--plot-to", plotTo, 0.0, 1e6, "plot window end (s)");
  appkit::ParseCommandLine(app, argc, argv);

  const std::vector<FaceSpec> specs = {
    { "default face", appkit::DefaultFace(), "", VisemeSet::Paper6, "A", "MouthSmile", 1000.0 },
    { "ICT head", appkit::FaceKitPath("ict_head_full53.glb"), appkit::DataPath("rigs/arkit.json"),
      VisemeSet::Oculus15, "aa", "MouthSmile", 1000.0 },
    { "MakeHuman avatar", appkit::AvatarPath("makehuman_avatar.glb"),
      appkit::DataPath("rigs/readyplayerme.json"), VisemeSet::Oculus15, "aa", "MouthSmile",
      1000.0 },
  };
  try
  {
    appkit::MakeFolder(out);
    const std::string text = morphnode::text::ReadFile(textFile, "text");
    std::map<VisemeSet, Utterance> spoken;
    std::vector<Row> rows;
    std::ofstream frames(out + "/bilabials.csv");
    frames << "face,method,decision,frame,time,gap_mm,rest_mm\n";
    std::vector<vtkSmartPointer<vtkImageData>> sheetRows;
    vtkNew<vtkTable> plot;
    for (const FaceSpec& spec : specs)
    {
      if (!std::ifstream(spec.File))
      {
        std::cout << spec.Name << ": not found at " << spec.File << ", left out\n";
        continue;
      }
      const auto face = LoadStudyFace(spec);
      SpeechOptions options;
      options.Visemes = spec.Visemes;
      options.Coarticulation.FrameRate = 30.0;
      auto found = spoken.find(spec.Visemes);
      if (found == spoken.end())
      {
        found = spoken.emplace(spec.Visemes, SpeakText(text, options)).first;
      }
      const Utterance& speech = found->second;
      const VisemeMap map = SelectVisemeMap(options);
      const auto bilabials = BilabialFrames(speech, map, options.Coarticulation.Lead);
      const double eps = 0.005 * face->Diagonal;
      const std::vector<double> none =
        LipGaps(*face, speech.Visemes, OptimizerSettings{}, Decide::PerShape);
      std::cout << spec.Name << ": " << speech.Visemes.GetNumberOfFrames() << " frames, "
                << bilabials.size() << " bilabials, rest gap " << face->RestGap() << " mm, eps "
                << eps * 1000.0 << " mm\n";
      size_t worstFrame = bilabials.empty() ? 0 : bilabials[0];
      double worstGap = -1e300;
      for (int m = 0; m < NumberOfOptimizerPresets; ++m)
      {
        const auto preset = static_cast<OptimizerPreset>(m);
        const OptimizerSettings s = MakeOptimizerSettings(preset, threshold, eps);
        for (Decide decide : { Decide::PerTarget, Decide::PerShape })
        {
          if (m == 0 && decide == Decide::PerTarget)
          {
            continue; // unoptimized: the same either way
          }
          const auto gaps = LipGaps(*face, speech.Visemes, s, decide);
          Row row;
          row.Face = spec.Name;
          row.Method = OptimizerPresetName(preset);
          row.Decision = m == 0 ? "-" : decide == Decide::PerShape ? "per shape" : "per target";
          row.Bilabials = static_cast<int>(bilabials.size());
          row.WorstGap = -1e300;
          for (size_t f : bilabials)
          {
            const double g = GapNear(gaps, f) - face->RestGap();
            row.Open += g > 0.5 ? 1 : 0;
            row.MeanGap += g / static_cast<double>(bilabials.size());
            row.WorstGap = std::max(row.WorstGap, g);
            frames << spec.Name << "," << row.Method << "," << row.Decision << "," << f << ","
                   << f / speech.Visemes.GetFrameRate() << "," << GapNear(gaps, f) << ","
                   << face->RestGap() << "\n";
            if (preset == OptimizerPreset::Adjusted && decide == Decide::PerTarget && g > worstGap)
            {
              worstGap = g;
              worstFrame = f;
            }
          }
          for (size_t f = 0; f < gaps.size(); ++f)
          {
            row.OverOpen = std::max(row.OverOpen, gaps[f] - none[f]);
          }
          rows.push_back(row);
          if (spec.Name == "ICT head" && (m == 0 || preset == OptimizerPreset::Adjusted))
          {
            if (plot->GetNumberOfColumns() == 0)
            {
              vtkNew<vtkFloatArray> time;
              time->SetName("time (s)");
              plot->AddColumn(time);
              const size_t first = static_cast<size_t>(plotFrom * speech.Visemes.GetFrameRate());
              const size_t last =
                std::min(gaps.size(), static_cast<size_t>(plotTo * speech.Visemes.GetFrameRate()));
              plot->SetNumberOfRows(static_cast<vtkIdType>(last - first));
              for (size_t f = first; f < last; ++f)
              {
                plot->SetValue(
                  static_cast<vtkIdType>(f - first), 0, f / speech.Visemes.GetFrameRate());
              }
            }
            vtkNew<vtkFloatArray> column;
            const std::string name =
              m == 0 ? std::string("unoptimized") : std::string("adjusted, ") + row.Decision;
            column->SetName(name.c_str());
            column->SetNumberOfValues(plot->GetNumberOfRows());
            const size_t first = static_cast<size_t>(plotFrom * speech.Visemes.GetFrameRate());
            for (vtkIdType r = 0; r < plot->GetNumberOfRows(); ++r)
            {
              column->SetValue(
                r, static_cast<float>(gaps[first + static_cast<size_t>(r)] - face->RestGap()));
            }
            plot->AddColumn(column);
          }
        }
      }
      // Contact sheet row: the worst bilabial of the default method per target, then per
      // shape; the rounded vowel before (the ARKit rig's earlier oh) and after.
      const OptimizerSettings adjusted =
        MakeOptimizerSettings(OptimizerPreset::Adjusted, threshold, eps);
      const std::string round = spec.RigFile.empty() ? "O" : "oh";
      std::vector<double> before = face->ExpandShape(round);
      if (spec.Name == "ICT head")
      {
        // The rig's oh until this study: jawOpen 0.4, mouthFunnel 0.4, mouthPucker 0.1.
        std::fill(before.begin(), before.end(), 0.0);
        for (const auto& [target, w] : std::map<std::string, double>{
               { "jawOpen", 0.4 }, { "mouthFunnel", 0.4 }, { "mouthPucker", 0.1 } })
        {
          before[static_cast<size_t>(std::find(face->Targets.begin(), face->Targets.end(), target) -
            face->Targets.begin())] = w;
        }
      }
      const int size = 280;
      std::ostringstream at;
      at << std::fixed << std::setprecision(2) << worstFrame / speech.Visemes.GetFrameRate()
         << " s";
      vtkNew<vtkImageAppend> row;
      row->SetAppendAxis(0);
      const std::vector<std::pair<std::vector<double>, std::string>> cells = {
        { FrameWeights(*face, speech.Visemes, worstFrame, adjusted, Decide::PerTarget),
          "p/b/m at " + at.str() + ",\nper target" },
        { FrameWeights(*face, speech.Visemes, worstFrame, adjusted, Decide::PerShape),
          "p/b/m at " + at.str() + ",\nper shape" },
        { before, round + ",\nbefore" },
        { face->ExpandShape(round), round + ",\nafter" },
      };
      for (const auto& cell : cells)
      {
        row->AddInputData(RenderMouth(*face, cell.first, spec.Name + ": " + cell.second, size));
      }
      std::cout << spec.Name << ": mouth width at rest "
                << face->MouthWidth(std::vector<double>(face->Targets.size(), 0.0)) << " mm, "
                << round << " before " << face->MouthWidth(before) << " mm, after "
                << face->MouthWidth(face->ExpandShape(round)) << " mm, aa/A "
                << face->MouthWidth(face->ExpandShape(spec.Open)) << " mm\n";
      row->Update();
      vtkSmartPointer<vtkImageData> image = vtkSmartPointer<vtkImageData>::New();
      image->DeepCopy(row->GetOutput());
      sheetRows.push_back(image);
    }

    std::ofstream md(out + "/summary.md"), csv(out + "/summary.csv");
    md << "| face | method | decided | open bilabials | mean gap (mm) | worst gap (mm) | most over "
          "unoptimized (mm) |\n"
       << "| --- | --- | --- | --- | --- | --- | --- |\n";
    csv << "face,method,decided,bilabials,open,mean_gap_mm,worst_gap_mm,over_open_mm\n";
    md << std::fixed << std::setprecision(2);
    for (const Row& r : rows)
    {
      md << "| " << r.Face << " | " << r.Method << " | " << r.Decision << " | " << r.Open << " / "
         << r.Bilabials << " | " << r.MeanGap << " | " << r.WorstGap << " | " << r.OverOpen
         << " |\n";
      csv << r.Face << "," << r.Method << "," << r.Decision << "," << r.Bilabials << "," << r.Open
          << "," << r.MeanGap << "," << r.WorstGap << "," << r.OverOpen << "\n";
    }
    md.close();
    csv.close();
    std::cout << "\n" << std::ifstream(out + "/summary.md").rdbuf() << "\n";

    if (plot->GetNumberOfColumns() > 1)
    {
      vtkNew<vtkContextView> view;
      view->GetRenderWindow()->SetSize(1000, 420);
      view->GetRenderer()->SetBackground(1, 1, 1);
      vtkNew<vtkChartXY> chart;
      chart->SetTitle(
        "ICT head: lip gap above rest, adjusted threshold 0.1 (0 = lips touch as at rest)");
      chart->GetAxis(vtkAxis::LEFT)->SetTitle("lip gap - rest gap (mm)");
      chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time (s)");
      chart->SetShowLegend(true);
      const unsigned char colors[3][3] = { { 120, 120, 120 }, { 214, 39, 40 }, { 31, 119, 180 } };
      for (vtkIdType c = 1; c < plot->GetNumberOfColumns() && c <= 3; ++c)
      {
        vtkPlot* line = chart->AddPlot(vtkChart::LINE);
        line->SetInputData(plot, 0, c);
        line->SetColor(colors[c - 1][0], colors[c - 1][1], colors[c - 1][2], 255);
        line->SetWidth(c == 1 ? 3.0f : 1.8f);
      }
      view->GetScene()->AddItem(chart);
      appkit::WritePng(view, out + "/lip_gap_over_time.png");
    }
    if (!sheetRows.empty())
    {
      vtkNew<vtkImageAppend> sheet;
      sheet->SetAppendAxis(1);
      for (auto it = sheetRows.rbegin(); it != sheetRows.rend(); ++it) // image rows go up
      {
        sheet->AddInputData(*it);
      }
      vtkNew<vtkPNGWriter> writer;
      writer->SetInputConnection(sheet->GetOutputPort());
      writer->SetFileName((out + "/lips_contact_sheet.png").c_str());
      writer->Write();
    }
    std::cout << "wrote " << out
              << "/summary.md, summary.csv, bilabials.csv, lip_gap_over_time.png, "
              << "lips_contact_sheet.png\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "LipGapStudy: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
