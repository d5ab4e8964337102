// The checkpoint cadence and the stop decision must be the same on every rank: a signal that
// reached one rank only stops all of them at the same step, and the step cadence is exact.
#include "core/stop_signal.hpp"
#include "par/checkpoint_clock.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <thread>

namespace texsim::par {
namespace {

TEST(CheckpointClock, StepCadenceWithoutWallClock) {
  CheckpointClock clock(world(), 5, 0.0);
  for (std::int64_t done = 1; done <= 20; ++done) {
    const auto decision = clock.after_step(done);
    EXPECT_EQ(decision.checkpoint, done % 5 == 0) << done;
    EXPECT_FALSE(decision.stop);
  }
}

TEST(CheckpointClock, WallClockCadence) {
  // A cadence of 1 ms and steps of 5 ms: every step is due, and only rank 0's clock decides.
  CheckpointClock clock(world(), 0, 1e-3 / 60.0);
  for (std::int64_t done = 1; done <= 3; ++done) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_TRUE(clock.after_step(done).checkpoint) << done;
  }
  CheckpointClock never(world(), 0, 0.0);
  EXPECT_FALSE(never.after_step(1).checkpoint);
}

TEST(CheckpointClock, DefaultMinutesOnOneNode) {
  EXPECT_EQ(default_checkpoint_minutes(world()), 60.0);
}

// Last: the handler keeps the signal for the rest of the program.
TEST(CheckpointClock, ASignalOnTheLastRankStopsEveryRank) {
  const Comm comm = world();
  install_stop_signal_handlers();
  CheckpointClock clock(comm, 0, 0.0);
  EXPECT_FALSE(clock.after_step(1).stop);
  EXPECT_EQ(clock.agreed_stop_signal(), 0);
  if (comm.rank == comm.size - 1)
    std::raise(SIGUSR1);
  const auto decision = clock.after_step(2);
  EXPECT_TRUE(decision.stop);
  EXPECT_TRUE(decision.checkpoint);
  EXPECT_EQ(decision.signal_number, SIGUSR1);
  EXPECT_EQ(clock.agreed_stop_signal(), SIGUSR1);
}

} // namespace
} // namespace texsim::par
