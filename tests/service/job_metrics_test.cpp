// The executor's stage histograms and failure counters in Prometheus' text format, read back by a
// strict parser (prometheus_text.h): known observations land in the right buckets, cumulatively,
// with the exact sum and count; failures are counted by stage and cause; label values are escaped.
#include "service/job_metrics.h"

#include <gtest/gtest.h>

#include "prometheus_text.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

TEST(JobMetrics, StageSecondsAreACumulativeHistogramPerStage) {
  JobMetrics m;
  for (double s : {0.5, 3.0, 3.0, 200.0, 5000.0}) m.observe_stage("train", s);
  m.observe_stage("capture", 1.0);  // on a bound: counted in that bucket (le is "<=")
  m.observe_stage("", 1.0);         // no stage: not counted
  m.observe_stage("fit", -1.0);     // a clock that went back: not counted
  const PromText t = parse_prometheus(m.prometheus_text());
  EXPECT_EQ(t.types.at("lorgnette_stage_seconds"), "histogram");
  EXPECT_TRUE(histogram_errors(t).empty());
  auto bucket = [&](const std::string& stage, const std::string& le) {
    return t.value("lorgnette_stage_seconds_bucket", {{"stage", stage}, {"le", le}});
  };
  EXPECT_EQ(bucket("train", "1"), 1);
  EXPECT_EQ(bucket("train", "5"), 3);
  EXPECT_EQ(bucket("train", "120"), 3);
  EXPECT_EQ(bucket("train", "300"), 4);
  EXPECT_EQ(bucket("train", "3600"), 4);
  EXPECT_EQ(bucket("train", "+Inf"), 5);
  EXPECT_DOUBLE_EQ(t.value("lorgnette_stage_seconds_sum", {{"stage", "train"}}), 5206.5);
  EXPECT_EQ(t.value("lorgnette_stage_seconds_count", {{"stage", "train"}}), 5);
  EXPECT_EQ(bucket("capture", "1"), 1);
  EXPECT_TRUE(std::isnan(bucket("fit", "+Inf")));
  EXPECT_TRUE(std::isnan(bucket("", "+Inf")));
}

TEST(JobMetrics, FailuresAreCountedByStageAndCause) {
  JobMetrics m;
  m.count_failure("capture", "refused");
  m.count_failure("capture", "refused");
  m.count_failure("train", "crashed");
  m.count_failure("", "start");
  m.count_failure("fit\"\n", "refused");  // a strange stage name stays one well-formed line
  const PromText t = parse_prometheus(m.prometheus_text());
  EXPECT_EQ(t.types.at("lorgnette_job_failures_total"), "counter");
  auto failures = [&](const std::string& stage, const std::string& cause) {
    return t.value("lorgnette_job_failures_total", {{"stage", stage}, {"cause", cause}});
  };
  EXPECT_EQ(failures("capture", "refused"), 2);
  EXPECT_EQ(failures("train", "crashed"), 1);
  EXPECT_EQ(failures("start", "start"), 1);
  EXPECT_EQ(failures("fit\\\"\\n", "refused"), 1);  // as escaped on the wire
}

TEST(PrometheusText, TheReaderRefusesMalformedText) {
  EXPECT_THROW(parse_prometheus("x 1\n"), std::runtime_error);  // no TYPE
  EXPECT_THROW(parse_prometheus("# TYPE x gauge\nx{a=1} 1\n"), std::runtime_error);
  EXPECT_THROW(parse_prometheus("# TYPE x gauge\nx one\n"), std::runtime_error);
  const PromText bad = parse_prometheus(
      "# TYPE h histogram\nh_bucket{le=\"1\"} 3\nh_bucket{le=\"+Inf\"} 2\nh_sum 1\nh_count 2\n");
  EXPECT_FALSE(histogram_errors(bad).empty());
}
