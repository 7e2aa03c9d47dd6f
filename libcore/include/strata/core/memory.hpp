#pragma once
/// Memory use of this process, for reports and benchmarks (Linux /proc/self/status), and the
/// machine's memory, for refusing models that cannot fit.
#include <cstddef>

namespace strata::sys {

/// Resident memory now (VmRSS), bytes; 0 where unavailable.
std::size_t rss_bytes();
/// Peak resident memory so far (VmHWM), bytes; 0 where unavailable.
std::size_t peak_rss_bytes();
/// Physical memory of the machine, bytes; 0 where unavailable.
std::size_t physical_memory_bytes();

}  // namespace strata::sys
