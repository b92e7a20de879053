// SPDX-License-Identifier: BSD-3-Clause
// vtkBehaviorTimeSource's script properties (ScriptFileName, Script): what ParaView's proxy
// sets. They replace the commands when they change, fail clearly on a bad script, and
// change MTime only when their value changes. Speech-free scripts, so that the test also
// runs in a build without eSpeak NG.
#include "vtkBehaviorTimeSource.h"

#include "vtkAbstractArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"
#include "vtkVariant.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace
{
/// The value of a channel at `time` on port 0, NaN when the source fails.
double ChannelAt(vtkBehaviorTimeSource* source, const char* channel, double time)
{
  if (!source->UpdateTimeStep(time))
  {
    return std::nan("");
  }
  vtkTable* table = vtkTable::SafeDownCast(source->GetOutputDataObject(0));
  vtkAbstractArray* column = table ? table->GetColumnByName(channel) : nullptr;
  return column && table->GetNumberOfRows() == 1 ? column->GetVariantValue(0).ToDouble()
                                                 : std::nan("");
}

const char* const SmileAtOne = "duration 4\nat 1.0 gesture smile duration 1.5 intensity 1\n";
const char* const BrowsAtOne = "duration 4\nat 1.0 gesture raise_brows duration 1.5 intensity 1\n";
} // namespace

TEST(BehaviorTimeSourceProperties, ScriptTextDrivesTheChannelsAndReplacesOnChange)
{
  vtkNew<vtkBehaviorTimeSource> source;
  source->SetSeed(7);
  source->SetScript(SmileAtOne);
  EXPECT_STREQ(source->GetScript(), SmileAtOne);
  const double smile = ChannelAt(source, "MouthSmile", 1.75);
  ASSERT_FALSE(std::isnan(smile));
  EXPECT_GT(smile, 0.3) << "the script's smile gesture shows at its time";
  EXPECT_LT(ChannelAt(source, "MouthSmile", 0.2), 0.5 * smile) << "and not before";

  // Another script replaces the first: no smile left, raised brows instead.
  source->SetScript(BrowsAtOne);
  EXPECT_LT(ChannelAt(source, "MouthSmile", 1.75), 0.5 * smile)
    << "changing the Script property replaces its commands, it does not add to them";
  EXPECT_GT(ChannelAt(source, "BrowsUp", 1.75), 0.3);

  // The duration of the script is the source's.
  source->UpdateInformation();
  double range[2] = { 0, 0 };
  source->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range);
  EXPECT_DOUBLE_EQ(range[1], 4.0);
}

TEST(BehaviorTimeSourceProperties, ScriptFileAndTextAddUp)
{
  vtkNew<vtkBehaviorTimeSource> source;
  const std::string file = std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/idle.txt";
  source->SetScriptFileName(file.c_str());
  EXPECT_EQ(std::string(source->GetScriptFileName()), file);
  source->SetScript("at 1.0 gesture smile duration 1.5 intensity 1\n");
  EXPECT_GT(ChannelAt(source, "MouthSmile", 1.75), 0.3) << "the text's command on top of the file";
  source->SetScriptFileName("");
  EXPECT_FALSE(std::isnan(ChannelAt(source, "MouthSmile", 1.75)));
}

TEST(BehaviorTimeSourceProperties, SameValueKeepsMTimeNewValueBumpsIt)
{
  vtkNew<vtkBehaviorTimeSource> source;
  source->SetScript(SmileAtOne);
  const vtkMTimeType before = source->GetMTime();
  source->SetScript(SmileAtOne);
  EXPECT_EQ(source->GetMTime(), before) << "setting the same script is no change";
  source->SetScript(BrowsAtOne);
  EXPECT_GT(source->GetMTime(), before);
  source->SetScriptFileName(nullptr);
  EXPECT_STREQ(source->GetScriptFileName(), "");
}

TEST(BehaviorTimeSourceProperties, BadScriptFailsUntilFixed)
{
  vtkNew<vtkBehaviorTimeSource> source;
  source->GlobalWarningDisplayOff();
  source->SetScript("at 1.0 gesture no_such_gesture duration 1\n");
  EXPECT_EQ(source->UpdateTimeStep(1.0), 0) << "a bad script makes the update fail";
  EXPECT_EQ(source->UpdateTimeStep(1.5), 0) << "and it keeps failing: no half-applied script";
  source->SetScriptFileName("/no/such/script.txt");
  source->SetScript("");
  EXPECT_EQ(source->UpdateTimeStep(1.0), 0) << "an unreadable script file is an error too";
  source->SetScriptFileName("");
  source->SetScript(SmileAtOne);
  EXPECT_GT(ChannelAt(source, "MouthSmile", 1.75), 0.3) << "a good script works again";
}
