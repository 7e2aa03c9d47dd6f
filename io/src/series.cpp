#include "strata/io/series.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "atomic_file.hpp"
#include "strata/core/error.hpp"
#include "strata/core/log.hpp"
#include "strata/io/vtk.hpp"

namespace strata::io {
namespace fs = std::filesystem;

namespace {
std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string xml_unescape(const std::string& s) {
  static const std::pair<const char*, char> kEntities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    bool done = false;
    if (s[i] == '&')
      for (auto [ent, ch] : kEntities)
        if (s.compare(i, std::char_traits<char>::length(ent), ent) == 0) {
          out += ch;
          i += std::char_traits<char>::length(ent);
          done = true;
          break;
        }
    if (!done) out += s[i++];
  }
  return out;
}

/// Value of attribute `name` inside one XML start tag, or empty.
std::string attribute(const std::string& tag, const std::string& name) {
  for (std::size_t pos = 0; (pos = tag.find(name, pos)) != std::string::npos; pos += name.size()) {
    const bool starts_word = pos > 0 && (tag[pos - 1] == ' ' || tag[pos - 1] == '\t' || tag[pos - 1] == '\n');
    std::size_t p = pos + name.size();
    while (p < tag.size() && (tag[p] == ' ' || tag[p] == '\t')) ++p;
    if (!starts_word || p >= tag.size() || tag[p] != '=') continue;
    ++p;
    while (p < tag.size() && (tag[p] == ' ' || tag[p] == '\t')) ++p;
    if (p >= tag.size() || (tag[p] != '"' && tag[p] != '\'')) continue;
    const char q = tag[p];
    const auto end = tag.find(q, p + 1);
    if (end == std::string::npos) continue;
    return xml_unescape(tag.substr(p + 1, end - p - 1));
  }
  return {};
}
}  // namespace

std::vector<PvdEntry> read_pvd(const fs::path& pvd) {
  std::ifstream in(pvd, std::ios::binary);
  STRATA_CHECK(in, IO, "cannot open {}", pvd.string());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  // A series file strata (or ParaView) wrote ends with </Collection> and </VTKFile>: without
  // them it was cut short, and the frames it lists may not be all there are.
  STRATA_CHECK(text.find("<Collection") != std::string::npos &&
                   text.find("</Collection>") != std::string::npos &&
                   text.find("</VTKFile>") != std::string::npos,
               IO,
               "{} is damaged or not a ParaView series: a .pvd file holds <VTKFile type=\"Collection\"> "
               "with a <Collection> of <DataSet> entries, closed by </Collection> and </VTKFile>",
               pvd.string());
  std::vector<PvdEntry> out;
  for (std::size_t pos = 0; (pos = text.find("<DataSet", pos)) != std::string::npos;) {
    const auto end = text.find('>', pos);
    STRATA_CHECK(end != std::string::npos, IO, "{}: unterminated <DataSet> element", pvd.string());
    const std::string tag = text.substr(pos, end - pos);
    PvdEntry e;
    const auto t = attribute(tag, "timestep");
    char* t_end = nullptr;
    e.time = t.empty() ? 0.0 : std::strtod(t.c_str(), &t_end);
    STRATA_CHECK(t.empty() || (t_end && *t_end == '\0' && std::isfinite(e.time)), IO,
                 "{}: <DataSet> with timestep=\"{}\", which is not a number", pvd.string(), t);
    const auto part = attribute(tag, "part");
    e.part = part.empty() ? 0 : std::atoi(part.c_str());
    e.file = attribute(tag, "file");
    STRATA_CHECK(!e.file.empty(), IO, "{}: <DataSet> without a file attribute", pvd.string());
    out.push_back(std::move(e));
    pos = end;
  }
  return out;
}

bool is_mesh_series(const fs::path& pvd) {
  const auto entries = read_pvd(pvd);
  return !entries.empty() && entries.front().file.extension() == ".vtu";
}

void write_pvd(const fs::path& pvd, const std::vector<PvdEntry>& entries) {
  std::string text =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const auto& e : entries)
    text += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"{}\" file=\"{}\"/>\n", e.time, e.part,
                        xml_escape(e.file.generic_string()));
  text += "  </Collection>\n</VTKFile>\n";
  detail::write_text_atomic(pvd, text);
}

Series::Series(fs::path dir, std::string name, Mode mode) : dir_(std::move(dir)), name_(std::move(name)) {
  STRATA_CHECK(!name_.empty() && name_.find('/') == std::string::npos, Input,
               "series name '{}' must be non-empty and contain no '/'", name_);
  std::error_code ec;
  fs::create_directories(dir_, ec);
  STRATA_CHECK(!ec, IO, "cannot create output folder {}: {}", dir_.string(), ec.message());
  if (mode == Mode::Resume && fs::exists(pvd_path())) {
    entries_ = read_pvd(pvd_path());
    renumber();
  }
  const std::size_t n = remove_unlisted(mode == Mode::Fresh);
  if (n > 0 && mode == Mode::Fresh)
    log::info("{}: removed the {} files of an earlier '{}' series (frames, .pvd, unfinished .tmp files)",
              dir_.string(), n, name_);
  else if (n > 0)
    log::warn(
        "{}: removed {} file{} of the '{}' series that its .pvd does not list (written by a run that was "
        "killed before listing them)",
        dir_.string(), n, n == 1 ? "" : "s", name_);
}

std::size_t Series::remove_unlisted(bool pvd_too) {
  // <name>_<digits>.vtp|.vtu and their .tmp, <name>.pvd.tmp; <name>.pvd itself when asked.
  const std::string prefix = name_ + "_";
  auto is_frame = [&](std::string fn) {
    if (fn.ends_with(".tmp")) fn.resize(fn.size() - 4);
    if (!fn.starts_with(prefix) || !(fn.ends_with(".vtp") || fn.ends_with(".vtu"))) return false;
    const std::string digits = fn.substr(prefix.size(), fn.size() - prefix.size() - 4);
    return !digits.empty() &&
           std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  std::set<std::string> listed;
  for (const auto& e : entries_) listed.insert(e.file.filename().string());
  std::size_t removed = 0;
  std::error_code ec;
  for (const auto& f : fs::directory_iterator(dir_, ec)) {
    const std::string fn = f.path().filename().string();
    const bool stale =
        (is_frame(fn) && !listed.count(fn)) || fn == name_ + ".pvd.tmp" || (pvd_too && fn == name_ + ".pvd");
    if (stale && fs::remove(f.path(), ec)) ++removed;
  }
  return removed;
}

void Series::renumber() {
  // Frame numbers continue after the highest one listed.
  const std::string prefix = name_ + "_";
  next_index_ = static_cast<std::int64_t>(entries_.size());
  for (const auto& e : entries_) {
    const std::string fn = e.file.filename().string();
    if (fn.starts_with(prefix))
      next_index_ = std::max<std::int64_t>(next_index_, std::atoll(fn.c_str() + prefix.size()) + 1);
  }
}

fs::path Series::next_frame_path(const std::string& ext) const {
  return dir_ / fmt::format("{}_{:06d}{}", name_, next_index_, ext);
}

fs::path Series::add_frame(double time, const std::function<void(const fs::path&)>& write,
                           const std::string& ext) {
  const fs::path path = next_frame_path(ext);
  write(path);
  STRATA_CHECK(fs::exists(path), IO, "series {}: frame {} was not written", name_, path.string());
  entries_.push_back({time, path.filename(), 0});
  ++next_index_;
  write_pvd(pvd_path(), entries_);
  return path;
}

fs::path Series::add_particles(double time, const PointCloud& particles) {
  return add_frame(time, [&](const fs::path& p) { write_particles(p, particles); });
}

fs::path Series::add_lines(double time, const PointCloud& points, const LineSet& lines) {
  return add_frame(time, [&](const fs::path& p) { write_lines(p, points, lines); });
}

fs::path Series::add_mesh(double time, const MeshFrame& mesh) {
  return add_frame(
      time, [&](const fs::path& p) { write_mesh(p, mesh); }, ".vtu");
}

void Series::truncate_after(double time) {
  std::erase_if(entries_, [time](const PvdEntry& e) { return e.time > time; });
  renumber();
  write_pvd(pvd_path(), entries_);
  if (const std::size_t n = remove_unlisted(false))
    log::info("{}: removed {} '{}' frame{} written after the checkpoint", dir_.string(), n, name_,
              n == 1 ? "" : "s");
}

}  // namespace strata::io
