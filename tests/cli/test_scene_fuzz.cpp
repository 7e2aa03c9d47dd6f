// Mutation fuzzing of the example scenes: a fixed seed, a few hundred mutants (values swapped
// for hostile ones, numbers scaled, lines deleted or doubled, keys renamed, files cut short,
// stray bytes), each checked with `strata check` under a time limit. Whatever a mutant does,
// strata must end with exit status 0, 1 or 2, within the limit, and an exit-2 message must
// name the place in the scene (file:line:col) that caused it. A failing mutant is kept in
// the test's folder so that it can be replayed by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_test_util.hpp"

using namespace cli_test;

namespace {

constexpr unsigned kSeed = 20261124;
constexpr int kMutantsPerScene = 8;
constexpr int kSecondsPerMutant = 30;  // a hang, not a slow check: checks take well under a second

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

/// Index of a random `key = value` line (not a comment, header or blank), or -1.
int pick_assignment(const std::vector<std::string>& lines, std::mt19937& rng) {
  std::vector<int> idx;
  for (int i = 0; i < int(lines.size()); ++i) {
    const auto& l = lines[std::size_t(i)];
    const auto eq = l.find('=');
    if (eq != std::string::npos && !l.empty() && l[0] != '#' && l[0] != '[') idx.push_back(i);
  }
  if (idx.empty()) return -1;
  return idx[std::uniform_int_distribution<std::size_t>(0, idx.size() - 1)(rng)];
}

/// One mutation of a scene text; `what` says which, for the failure message.
std::string mutate(const std::string& text, std::mt19937& rng, std::string& what) {
  static const std::vector<std::string> hostile = {"0",
                                                   "-1",
                                                   "1e-320",
                                                   "1e308",
                                                   "-1e308",
                                                   "nan",
                                                   "inf",
                                                   "-inf",
                                                   "4294967297",
                                                   "-4294967297",
                                                   "9223372036854775807",
                                                   "\"\"",
                                                   "\"x\"",
                                                   "true",
                                                   "[]",
                                                   "[1e308, -1]",
                                                   "0.5",
                                                   "1e-9",
                                                   "1e9",
                                                   "[0.0, 0.0, 0.0]",
                                                   "\"../../nowhere.geo\"",
                                                   "{}",
                                                   "[[1, 2], [3]]",
                                                   "2147483648"};
  static const std::vector<double> factors = {0, -1, 1e-6, 1e-3, 1e-1, 10, 1e3, 1e6, 1e300};
  auto lines = lines_of(text);
  const int op = std::uniform_int_distribution<int>(0, 99)(rng);
  const int i = pick_assignment(lines, rng);
  auto any = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  if (i >= 0 && op < 40) {  // a hostile value
    auto& l = lines[std::size_t(i)];
    const std::string v = hostile[any(hostile.size())];
    what = "value of line " + std::to_string(i + 1) + " -> " + v;
    l = l.substr(0, l.find('=') + 1) + " " + v;
  } else if (i >= 0 && op < 62) {  // a number scaled
    auto& l = lines[std::size_t(i)];
    static const std::regex number(R"([-+]?[0-9]+\.?[0-9]*([eE][-+]?[0-9]+)?)");
    const auto eq = l.find('=');
    std::smatch m;
    std::string rhs = l.substr(eq + 1);
    if (!std::regex_search(rhs, m, number)) return mutate(text, rng, what);
    const double f = factors[any(factors.size())];
    std::ostringstream v;
    v.precision(17);
    v << std::stod(m.str()) * f;
    std::string scaled = v.str();
    if (scaled.find_first_of(".eEn") == std::string::npos &&
        m.str().find_first_of(".eE") != std::string::npos)
      scaled += ".0";  // keep a real a real
    what = "number on line " + std::to_string(i + 1) + " x " + std::to_string(f);
    l = l.substr(0, eq + 1) + rhs.substr(0, std::size_t(m.position())) + scaled +
        rhs.substr(std::size_t(m.position() + m.length()));
  } else if (i >= 0 && op < 72) {  // a line deleted
    what = "line " + std::to_string(i + 1) + " deleted";
    lines.erase(lines.begin() + i);
  } else if (i >= 0 && op < 78) {  // a line doubled
    what = "line " + std::to_string(i + 1) + " doubled";
    lines.insert(lines.begin() + i, lines[std::size_t(i)]);
  } else if (i >= 0 && op < 86) {  // a key renamed to another key of the file
    const int j = pick_assignment(lines, rng);
    auto key = [](const std::string& l) { return l.substr(0, l.find('=')); };
    what = "key of line " + std::to_string(i + 1) + " renamed from line " + std::to_string(j + 1);
    lines[std::size_t(i)] =
        key(lines[std::size_t(j)]) + lines[std::size_t(i)].substr(lines[std::size_t(i)].find('='));
  } else if (op < 91) {  // cut short
    const std::size_t at = any(text.size());
    what = "cut at byte " + std::to_string(at);
    return text.substr(0, at);
  } else if (op < 96) {  // a table header doubled or renamed
    std::vector<int> headers;
    for (int k = 0; k < int(lines.size()); ++k)
      if (!lines[std::size_t(k)].empty() && lines[std::size_t(k)][0] == '[') headers.push_back(k);
    if (headers.empty()) return mutate(text, rng, what);
    const int h = headers[any(headers.size())], g = headers[any(headers.size())];
    what = "header of line " + std::to_string(h + 1) + " replaced by line " + std::to_string(g + 1);
    lines[std::size_t(h)] = lines[std::size_t(g)];
  } else {  // stray bytes
    std::string t = text;
    const std::size_t at = any(t.size() + 1);
    static const std::string junk = "\"'[]{}=#,.\\\n\t\x01\xff\xc3";
    const char c = junk[any(junk.size())];
    what =
        "byte " + std::to_string(int(static_cast<unsigned char>(c))) + " inserted at " + std::to_string(at);
    return t.insert(at, 1, c);
  }
  return join_lines(lines);
}

}  // namespace

TEST(SceneFuzz, MutatedExampleScenesEndCleanlyWithLocatedErrors) {
  const fs::path examples = fs::path(STRATA_SOURCE_DIR) / "examples";
  std::vector<fs::path> scenes;
  for (const auto& d : fs::directory_iterator(examples))
    if (d.is_directory())
      for (const auto& f : fs::directory_iterator(d.path()))
        if (f.path().extension() == ".toml") scenes.push_back(f.path());
  std::sort(scenes.begin(), scenes.end());
  ASSERT_GE(scenes.size(), 10u);

  const fs::path work = temp_dir("fuzz");
  // STRATA_FUZZ_SEED explores other mutants by hand; CI keeps the fixed seed.
  const char* seed = std::getenv("STRATA_FUZZ_SEED");
  std::mt19937 rng(seed ? unsigned(std::strtoul(seed, nullptr, 10)) : kSeed);
  struct Mutant {
    fs::path file;
    std::string id;
    Result result;
  };
  std::vector<Mutant> mutants;
  for (const fs::path& scene : scenes) {
    // The mutant lives in a copy of the example's folder, beside the geometry files it names.
    const fs::path dir = work / scene.parent_path().filename();
    if (!fs::exists(dir)) {
      fs::create_directories(dir);
      for (const auto& f : fs::directory_iterator(scene.parent_path()))
        if (f.path().extension() == ".geo" || f.path().extension() == ".toml")
          fs::copy_file(f.path(), dir / f.path().filename());
    }
    std::ifstream in(scene);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    for (int k = 0; k < kMutantsPerScene; ++k) {
      std::string what;
      const std::string mutant = mutate(text, rng, what);
      const fs::path file = dir / ("mutant_" + scene.stem().string() + "_" + std::to_string(k) + ".toml");
      std::ofstream(file) << mutant;
      mutants.push_back({file, file.string() + " (" + scene.filename().string() + ": " + what + ")", {}});
    }
  }
  // Two checks at a time (the results do not depend on the order).
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t k; (k = next++) < mutants.size();)
      mutants[k].result = strata_within(kSecondsPerMutant, "check " + mutants[k].file.string());
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < 2; ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();

  const std::regex located(R"(\.toml:[0-9]+:[0-9]+: )");
  int status_counts[3] = {0, 0, 0}, failures = 0;
  for (const Mutant& m : mutants) {
    const Result& r = m.result;
    bool bad = true;
    if (r.status == 124 || r.status == 137)
      ADD_FAILURE() << "hang (over " << kSecondsPerMutant << " s): " << m.id;
    else if (r.status < 0 || r.status > 2)
      ADD_FAILURE() << "exit status " << r.status << " (crash?): " << m.id << "\n" << r.output;
    else if (r.status == 2 && !std::regex_search(r.output, located))
      ADD_FAILURE() << "exit 2 without a scene location: " << m.id << "\n" << r.output;
    else if (r.output.find("internal error") != std::string::npos)
      ADD_FAILURE() << "internal error: " << m.id << "\n" << r.output;
    else
      bad = false;
    if (r.status >= 0 && r.status <= 2) ++status_counts[r.status];
    if (bad)
      ++failures;
    else
      fs::remove(m.file);
  }
  const int count = int(mutants.size());
  std::printf("%d mutants of %zu scenes: %d accepted, %d exit 1, %d refused with a location; %d failed\n",
              count, scenes.size(), status_counts[0], status_counts[1], status_counts[2], failures);
  // Most mutants must be refused: a fuzzer whose mutants all pass tests nothing.
  EXPECT_GT(status_counts[2], count / 3);
  if (failures == 0) fs::remove_all(work);
}
