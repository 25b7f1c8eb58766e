#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "app/report/plot_panel.h"
#include "app/report/report_charts.h"

namespace aerograsp {
namespace {
using ::testing::ElementsAre;
using ::testing::HasSubstr;

std::vector<double> Times(std::size_t n, double dt_s) {
  std::vector<double> t_s(n);
  for (std::size_t i = 0; i < n; ++i) t_s[i] = dt_s * double(i);
  return t_s;
}

bool Kept(const std::vector<std::size_t>& keep, std::size_t i) {
  return std::binary_search(keep.begin(), keep.end(), i);
}

TEST(DecimateForChartTest, AShortRecordKeepsEverySample) {
  const std::vector<double> t_s = Times(kChartFullSamples, 0.033);
  const ChartLine line{"v", std::vector<double>(t_s.size(), 1.0), {}, 1, false};
  const std::vector<std::size_t> keep = DecimateForChart(t_s, {line});
  ASSERT_EQ(keep.size(), t_s.size());
  EXPECT_EQ(keep.back(), t_s.size() - 1);
}

TEST(DecimateForChartTest, ALongRecordKeepsItsEndsPeaksAndGapsWithinTheBudget) {
  // An hour at 30 Hz: a slow sine with one sample spike, and a gap from 1000 s to 1000.5 s.
  const std::vector<double> t_s = Times(108000, 1.0 / 30.0);
  ChartLine line{"v", {}, {}, 1, false};
  for (double t : t_s) line.v.push_back(std::sin(0.01 * t));
  const std::size_t spike = 54321, gap0 = 30000, gap1 = 30015;
  line.v[spike] = 5.0;
  for (std::size_t i = gap0; i < gap1; ++i) line.v[i] = NAN;
  const std::vector<std::size_t> keep = DecimateForChart(t_s, {line});
  EXPECT_TRUE(std::is_sorted(keep.begin(), keep.end()));
  EXPECT_LE(keep.size(), kChartBuckets * 4 + 4);  // first, last, lowest, highest, the gap's ends
  EXPECT_EQ(keep.front(), 0u);
  EXPECT_EQ(keep.back(), t_s.size() - 1);
  EXPECT_TRUE(Kept(keep, spike));
  for (std::size_t i : {gap0 - 1, gap0, gap1 - 1, gap1}) EXPECT_TRUE(Kept(keep, i)) << i;
}

TEST(RoundTicksTest, TicksAreRoundMultiplesInsideTheRange) {
  const AxisTicks metres = RoundTicks(-0.137, 0.52, 6);
  EXPECT_THAT(metres.values, ElementsAre(0.0, 0.2, 0.4));
  EXPECT_EQ(metres.decimals, 1);
  const AxisTicks seconds = RoundTicks(0.0, 52.11, 12);
  ASSERT_EQ(seconds.values.size(), 11u);
  EXPECT_DOUBLE_EQ(seconds.values[1], 5.0);
  EXPECT_DOUBLE_EQ(seconds.values.back(), 50.0);
  EXPECT_EQ(seconds.decimals, 0);
  const AxisTicks small = RoundTicks(0.0031, 0.0139, 5);
  EXPECT_THAT(small.values, ElementsAre(0.004, 0.006, 0.008, 0.010, 0.012));
  EXPECT_EQ(small.decimals, 3);
  EXPECT_TRUE(RoundTicks(1.0, 1.0).values.empty());
  EXPECT_TRUE(RoundTicks(0.0, NAN).values.empty());
}

TEST(CategoryColorTest, TheFirstTwentySixAreDistinctAndTextStaysReadable) {
  for (std::size_t a = 0; a < 26; ++a) {
    for (std::size_t b = a + 1; b < 26; ++b) {
      const PlotColor ca = CategoryColor(a), cb = CategoryColor(b);
      EXPECT_GE(std::abs(ca.r - cb.r) + std::abs(ca.g - cb.g) + std::abs(ca.b - cb.b), 50)
          << a << " " << b;
    }
  }
  EXPECT_EQ(TextColorOn(PlotColor{0, 0, 0}).r, 255);
  EXPECT_EQ(TextColorOn(PlotColor{255, 255, 255}).r, 0);
}

TEST(WriteHtmlTimeChartTest, DataIsCompactJsonWithNullGapsAndNoMarkup) {
  TimeChart chart;
  chart.title = "a </script> title";
  chart.unit = "m";
  chart.t_s = {0.0, 0.0333, 1.5};
  chart.lines = {{"x", {0.123456, NAN, -2.0}, {1, 2, 3}, 2, false}};
  chart.markers = {{1.0, "switch 1"}};
  std::ostringstream html;
  WriteHtmlTimeChart(chart, html);
  EXPECT_THAT(html.str(), HasSubstr("\"t\":[0,0.03,1.5]"));
  EXPECT_THAT(html.str(), HasSubstr("\"v\":[0.1235,null,-2]"));
  EXPECT_THAT(html.str(), HasSubstr("\"color\":[3,2,1]"));
  EXPECT_THAT(html.str(), HasSubstr("a \\u003c/script> title"));
  EXPECT_THAT(html.str(), HasSubstr("{\"t\":1,\"label\":\"switch 1\"}"));
}

}  // namespace
}  // namespace aerograsp
