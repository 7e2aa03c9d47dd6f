// Options at and beyond their limits: refused with exit status 2 and a message, never
// wrapped round or passed on to a library that cannot take them.
#include <gtest/gtest.h>

#include <string>

#include "cli_test_util.hpp"

using namespace cli_test;

TEST(CliLimits, ThreadCountsBeyondTheLimitAreRefused) {
  const std::string scene = std::string(STRATA_SOURCE_DIR) + "/examples/01_uniaxial_compression/quick.toml";
  for (const char* n : {"100000", "2147483648", "4294967297", "-1"}) {
    const auto r =
        run_strata("run " + scene + " --threads " + n + " -o /tmp/strata_cli_limits_never_written");
    EXPECT_EQ(r.status, 2) << "--threads " << n << ": " << r.output;
    EXPECT_NE(r.output.find("--threads"), std::string::npos) << r.output;
  }
  EXPECT_EQ(run_strata("bench dem --threads 100000").status, 2);
}

// The benchmark's block steps to the same state whatever the thread count: its state hash is
// what a scaling curve over thread counts compares to show the runs did the same work. Both
// blocks hold more than 3 × 4096 particles (min_particles_per_thread), so three threads each
// step a range of their own.
TEST(CliLimits, BenchDemReportsTheSameStateHashForAnyThreadCount) {
  for (const char* dim : {"2", "3"}) {
    std::string hash;
    for (const char* t : {"1", "2", "3"}) {
      const auto r =
          run_strata(std::string("bench dem --dim ") + dim + " --particles 14000 --steps 10 --threads " + t);
      ASSERT_EQ(r.status, 0) << r.output;
      const auto at = r.output.find("\"state_hash\": \"");
      ASSERT_NE(at, std::string::npos) << r.output;
      const std::string h = r.output.substr(at + 15, 16);
      if (hash.empty()) hash = h;
      EXPECT_EQ(h, hash) << "--dim " << dim << " --threads " << t;
    }
  }
}
