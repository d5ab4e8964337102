#include "core/progress.hpp"
#include "core/stage_timers.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace texsim {
namespace {

TEST(Progress, LineShowsCountPercentRateAndEta) {
  const Progress progress("relax", 1000, "steps");
  EXPECT_EQ(progress.line(250, 10.0), "relax: 250/1000 (25%) 25 steps/s, elapsed 10.0s, ETA 30.0s");
  EXPECT_EQ(progress.line(0, 0.0), "relax: 0/1000 (0%) 0 steps/s, elapsed 0.0s, ETA ?");
}

TEST(Progress, DurationsReadNaturally) {
  EXPECT_EQ(format_duration(12.34), "12.3s");
  EXPECT_EQ(format_duration(185), "3m05s");
  EXPECT_EQ(format_duration(3720), "1h02m");
}

TEST(StageTimers, AccumulatesRepeatedStagesInFirstUseOrder) {
  StageTimers timers;
  for (int i = 0; i < 3; ++i) {
    {
      auto s = timers.scope("solve");
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    { auto s = timers.scope("output"); }
  }
  ASSERT_EQ(timers.stages().size(), 2u);
  EXPECT_EQ(timers.stages()[0].name, "solve");
  EXPECT_EQ(timers.stages()[0].calls, 3);
  EXPECT_GE(timers.stages()[0].wall_s, 0.015);
  EXPECT_EQ(timers.stages()[1].name, "output");
}

} // namespace
} // namespace texsim
