#pragma once
/// Arrays whose first element starts a cache line. The DEM step reads and writes its particle
/// and bond arrays as whole vectors of up to 64 bytes, most of them from a block's first
/// particle on (a multiple of 256): starting at a cache line, each such vector lies in one
/// line. With the allocator's default alignment (16 bytes for large arrays) every 64-byte
/// vector spans two lines and costs two accesses.
#include <boost/align/aligned_allocator.hpp>

#include <cstddef>
#include <vector>

namespace strata {

inline constexpr std::size_t kCacheLine = 64;

/// A std::vector whose data starts at a multiple of kCacheLine (Boost.Align's allocator).
template <class T>
using aligned_vector = std::vector<T, boost::alignment::aligned_allocator<T, kCacheLine>>;

}  // namespace strata
