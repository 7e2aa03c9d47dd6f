#pragma once
// Read-back helpers for test_cli, in their own file: test_cli.cpp's `strata()` helper (run
// the command) would clash with the namespace of the strata headers.
#include <filesystem>
#include <string>
#include <vector>

/// What one written .vtp frame holds.
struct FrameCounts {
  std::size_t points = 0, lines = 0;
  std::vector<std::string> arrays;  ///< point-array names
};
FrameCounts frame_counts(const std::filesystem::path& vtp);
