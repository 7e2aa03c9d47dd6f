// Options at and beyond their limits: refused with exit status 2 and a message, never
// wrapped round or passed on to a library that cannot take them.
#include <gtest/gtest.h>

#include <string>

#include "cli_test_util.hpp"

using namespace cli_test;

TEST(CliLimits, ThreadCountsBeyondTheLimitAreRefused) {
  const std::string scene = std::string(STRATA_SOURCE_DIR) + "/examples/01_uniaxial_compression/quick.toml";
  for (const char* n : {"100000", "2147483648", "4294967297", "-1"}) {
    const auto r = strata("run " + scene + " --threads " + n + " -o /tmp/strata_cli_limits_never_written");
    EXPECT_EQ(r.status, 2) << "--threads " << n << ": " << r.output;
    EXPECT_NE(r.output.find("--threads"), std::string::npos) << r.output;
  }
  EXPECT_EQ(strata("bench dem --threads 100000").status, 2);
}
