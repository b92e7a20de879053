// SPDX-License-Identifier: BSD-3-Clause
// Weight requests by index and by name: the last set wins, names resolve against each
// model, the first bad request (in the order they were set) is the error, and the implicit
// neutral of a request that names only targets.
#include "base/Error.h"
#include "morph/WeightRequests.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace morphnode;

namespace
{
const std::vector<std::string> Face{ "Neutral", "jawOpen", "smile", "blink" };

std::string ErrorOf(const WeightRequests& requests)
{
  try
  {
    std::vector<double> w;
    requests.Resolve(w);
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(WeightRequests, DefaultsToTheNeutral)
{
  WeightRequests requests;
  requests.SetTargets(Face);
  std::vector<double> w;
  requests.Resolve(w);
  EXPECT_EQ(w, (std::vector<double>{ 1.0, 0.0, 0.0, 0.0 }));
  EXPECT_EQ(requests.Get(0), 1.0);
  EXPECT_EQ(requests.Get(2), 0.0);
  EXPECT_TRUE(requests.Empty());
  EXPECT_FALSE(requests.Clear());
}

TEST(WeightRequests, TheLastSetWinsWhetherByIndexOrByName)
{
  WeightRequests requests;
  requests.SetByName("smile", 0.4); // before any model
  EXPECT_EQ(requests.GetByName("smile"), 0.4);
  requests.SetTargets(Face);
  requests.SetByIndex(2, 0.9); // later: wins over the name
  requests.SetByIndex(1, 0.2);
  requests.SetByName("jawOpen", 0.6); // later: wins over the index
  std::vector<double> w;
  requests.Resolve(w);
  EXPECT_EQ(w, (std::vector<double>{ 1.0, 0.6, 0.9, 0.0 }));
  EXPECT_EQ(requests.Get(1), 0.6);
  EXPECT_EQ(requests.GetByName("smile"), 0.9);
  requests.SetByName("smile", 0.1);
  requests.Resolve(w);
  EXPECT_EQ(w[2], 0.1);
  EXPECT_EQ(requests.FindTarget("blink"), 3);
  EXPECT_EQ(requests.FindTarget("nope"), -1);
  EXPECT_EQ(requests.Describe(), "1=0.2 2=0.9 smile=0.1 jawOpen=0.6");
  EXPECT_TRUE(requests.Clear());
  requests.Resolve(w);
  EXPECT_EQ(w, (std::vector<double>{ 1.0, 0.0, 0.0, 0.0 }));
}

TEST(WeightRequests, NamesResolveAgainstEachModel)
{
  WeightRequests requests;
  requests.SetTargets(Face);
  requests.SetByName("blink", 0.5);
  std::vector<double> w;
  requests.Resolve(w);
  EXPECT_EQ(w[3], 0.5);
  requests.SetTargets({ "Neutral", "blink", "jawOpen" }); // another face: another index
  requests.Resolve(w);
  EXPECT_EQ(w, (std::vector<double>{ 1.0, 0.5, 0.0 }));
  requests.SetTargets({ "Neutral", "jawOpen" }); // a face without it
  EXPECT_NE(
    ErrorOf(requests).find("no target has that name; targets: Neutral jawOpen"), std::string::npos);
  EXPECT_EQ(requests.GetByName("blink"), 0.5); // the value set
}

TEST(WeightRequests, TheFirstBadRequestIsTheError)
{
  WeightRequests requests;
  requests.SetTargets(Face);
  requests.SetByIndex(7, 0.5);
  requests.SetByName("frown", 0.5);
  EXPECT_NE(
    ErrorOf(requests).find("a weight is set for target 7, but the input has 4 targets (0..3"),
    std::string::npos);
  WeightRequests named;
  named.SetTargets(Face);
  named.SetByName("frown", 0.5);
  named.SetByIndex(7, 0.5);
  EXPECT_NE(ErrorOf(named).find("target 'frown'"), std::string::npos);
  named.SetByName("frown", 0.5); // set again: later than the index now
  EXPECT_NE(ErrorOf(named).find("target 7"), std::string::npos);
}

TEST(WeightRequests, ImplicitNeutral)
{
  EXPECT_DOUBLE_EQ(ImplicitNeutralWeight({ 0.0, 0.25, 0.5 }), 0.25);
  EXPECT_EQ(ImplicitNeutralWeight({ 7.0, 0.75, 0.5 }), 0.0); // never negative; entry 0 not read
  EXPECT_EQ(ImplicitNeutralWeight({ 0.0 }), 1.0);
}
