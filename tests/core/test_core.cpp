#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/numbers.hpp>
#include <strata/core/parallel.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

using namespace strata;

TEST(Error, KindDecidesExitStatus) {
  EXPECT_EQ(Error(ErrorKind::Input, "x").exit_status(), 2);
  EXPECT_EQ(Error(ErrorKind::Unsupported, "x").exit_status(), 2);
  EXPECT_EQ(Error(ErrorKind::Numerical, "x").exit_status(), 1);
  EXPECT_EQ(Error(ErrorKind::IO, "x").exit_status(), 1);
}

TEST(Error, CheckThrowsWithFormattedValues) {
  try {
    const double kn = -5;
    STRATA_CHECK(kn > 0, Input, "kn = {} must be > 0 (N/m)", kn);
    FAIL() << "STRATA_CHECK did not throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input);
    EXPECT_STREQ(e.what(), "kn = -5 must be > 0 (N/m)");
  }
}

TEST(Error, MissingFeatureNamesTheOption) {
  try {
    fail_missing_feature("STRATA_WITH_GMSH", "reading .geo files");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_status(), 2);
    EXPECT_NE(std::string(e.what()).find("-DSTRATA_WITH_GMSH=ON"), std::string::npos);
  }
}

// A reduction must not depend on the thread count: sum values whose rounding depends on
// the order of addition, with 1, 2 and 3 threads, and require identical bits.
TEST(Parallel, SumIsBitIdenticalForAnyThreadCount) {
  const std::ptrdiff_t n = 1'000'003;
  auto term = [](std::ptrdiff_t i) { return std::sin(0.001 * double(i)) * 1e-3 + 1.0 / double(i + 1); };
  std::vector<double> sums;
  for (int t : {1, 2, 3}) {
    par::set_threads(t);
    sums.push_back(par::parallel_sum<double>(n, term));
  }
  par::set_threads(0);
  EXPECT_EQ(sums[0], sums[1]);
  EXPECT_EQ(sums[0], sums[2]);
  // And it is the sum (within rounding): compare with a serial Kahan sum.
  double s = 0, c = 0;
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const double y = term(i) - c, t = s + y;
    c = (t - s) - y;
    s = t;
  }
  EXPECT_NEAR(sums[0], s, 1e-9 * std::abs(s));
}

TEST(Parallel, RangesCoverEveryIndexOnce) {
  for (int t : {1, 2, 3}) {
    par::set_threads(t);
    std::vector<int> hits(10007, 0);
    par::parallel_ranges(std::ptrdiff_t(hits.size()), [&](std::ptrdiff_t b, std::ptrdiff_t e) {
      for (auto i = b; i < e; ++i) hits[std::size_t(i)] += 1;
    });
    for (int h : hits) ASSERT_EQ(h, 1);
  }
  par::set_threads(0);
}

TEST(Parallel, PagingInKeepsTheContents) {
  par::set_threads(2);
  // a range above page_in's 64 MiB, not on page boundaries: its whole pages are paged in, and
  // every byte, inside them or not, keeps its value
  std::vector<unsigned char> bytes(std::size_t{80} << 20, 0xa5);
  par::page_in(bytes.data() + 1, bytes.size() - 2);
  EXPECT_EQ(std::count(bytes.begin(), bytes.end(), 0xa5), std::ptrdiff_t(bytes.size()));
  // reserve_paged: the elements there are kept, the size too; the storage grows, and what a
  // resize then adds is value-initialised as ever
  std::vector<std::uint32_t> v(1000);
  std::iota(v.begin(), v.end(), 7u);
  const std::size_t n = std::size_t{20} << 20;  // 80 MiB of elements
  par::reserve_paged(v, n);
  EXPECT_EQ(v.size(), 1000u);
  EXPECT_GE(v.capacity(), n);
  for (std::size_t i = 0; i < v.size(); ++i) ASSERT_EQ(v[i], 7u + i);
  v.resize(n);
  EXPECT_EQ(std::count(v.begin() + 1000, v.end(), 0u), std::ptrdiff_t(n - 1000));
  par::set_threads(0);
}

TEST(Parallel, ThreadCountsAboveTheLimitAreRefused) {
  // OpenMP cannot start 100,000 threads (libgomp aborted); strata refuses before asking
  const int before = par::threads();
  EXPECT_THROW(par::set_threads(100000), Error);
  EXPECT_THROW(par::set_threads(par::kMaxThreads + 1), Error);
  EXPECT_EQ(par::threads(), before);
  EXPECT_NO_THROW(par::set_threads(before));
}

TEST(Numbers, ComparedValuesNeverPrintAlike) {
  const double crit = 1.434e-07, above = std::nextafter(crit, 1.0);
  const auto [a, b] = strata::distinct_pair(above, crit);
  EXPECT_NE(a, b);
  EXPECT_EQ(strata::distinct_pair(2.0, 3.0), (std::pair<std::string, std::string>{"2", "3"}));
  EXPECT_EQ(strata::distinct_pair(1.5e-7, 1.5e-7).first, "1.5e-07");
  EXPECT_EQ(strata::distinct_pair(above / crit, 1.0).second, "1");
  EXPECT_EQ(strata::ratio_text(3.0, 2.0), "1.500");
  EXPECT_NE(strata::ratio_text(above, crit), "1.000");  // just above 1 reads above 1
  EXPECT_EQ(strata::ratio_text(crit, crit), "1.000");
}
