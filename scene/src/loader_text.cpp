// Text of the loader's messages: names, suggestions for misspellings, counts and ranges.
#include "loader_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <sstream>

namespace strata::scene::text {

namespace {
const char* const kAxes[] = {"x", "y", "z"};
}  // namespace

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::size_t edit_distance(std::string_view a_in, std::string_view b_in) {
  const std::string a = lower(a_in), b = lower(b_in);
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

bool underscore_prefix(std::string_view word, std::string_view cand) {
  const std::string w = lower(word), c = lower(cand);
  const auto& shorter = w.size() < c.size() ? w : c;
  const auto& longer = w.size() < c.size() ? c : w;
  return shorter.size() >= 2 && longer.size() > shorter.size() &&
         longer.compare(0, shorter.size(), shorter) == 0 && longer[shorter.size()] == '_';
}

std::optional<std::string> closest(std::string_view word, const std::vector<std::string>& candidates) {
  const std::size_t limit = word.size() <= 4 ? 1 : word.size() <= 8 ? 2 : 3;
  std::optional<std::string> best;
  std::size_t best_d = limit + 1;
  for (const auto& c : candidates) {
    const std::size_t dist = edit_distance(word, c);
    if (dist < best_d && dist < std::min(word.size(), c.size())) best = c, best_d = dist;
  }
  if (best) return best;
  for (const auto& c : candidates)
    if (underscore_prefix(word, c)) return c;
  for (const auto& c : candidates)  // an abbreviation: "loc" for "local"
    if (word.size() >= 3 && c.size() > word.size() && lower(c).compare(0, word.size(), lower(word)) == 0)
      return c;
  return std::nullopt;
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates,
                         const char* quote) {
  auto c = closest(word, candidates);
  return c ? fmt::format("; did you mean {}{}{}?", quote, *c, quote) : "";
}

std::string join(const std::vector<std::string>& items, std::string_view sep) {
  std::string out;
  for (const auto& s : items) {
    if (!out.empty()) out += sep;
    out += s;
  }
  return out;
}

std::string bracket(const TableSpec& t) { return t.array ? "[[" + t.name + "]]" : "[" + t.name + "]"; }

std::vector<std::string> key_names(const TableSpec& t) {
  std::vector<std::string> out;
  for (const auto& k : t.keys) out.push_back(k.name);
  return out;
}

std::vector<std::string> table_names() {
  std::vector<std::string> out;
  for (const auto& t : schema()) out.push_back(t.name);
  return out;
}

const TableSpec* find_table(std::string_view name) {
  for (const auto& t : schema())
    if (t.name == name) return &t;
  return nullptr;
}

const KeySpec* find_key(const TableSpec& t, std::string_view name) {
  for (const auto& k : t.keys)
    if (k.name == name) return &k;
  return nullptr;
}

std::string unit_suffix(const KeySpec& k) { return k.unit.empty() ? "" : " (" + k.unit + ")"; }

std::string first_sentence(const std::string& doc) {
  // The first ". " that ends a sentence (not the one of an "et al." citation).
  std::size_t end = doc.find(". ");
  while (end != std::string::npos && end >= 5 && doc.compare(end - 5, 5, "et al") == 0)
    end = doc.find(". ", end + 2);
  std::string s = doc.substr(0, std::min(end, doc.find("; required")));
  if (!s.empty() && s.back() == '.') s.pop_back();
  // Lower-case a plain first word ("The", "Velocity,") but not a symbol ("Kn:", "Fs0:").
  std::size_t n = 0;
  while (n < s.size() && std::isalpha(static_cast<unsigned char>(s[n]))) ++n;
  const bool plain_word = n > 0 && (n == s.size() || s[n] == ' ' || s[n] == ',') &&
                          std::all_of(s.begin() + 1, s.begin() + static_cast<std::ptrdiff_t>(n),
                                      [](char c) { return std::islower(static_cast<unsigned char>(c)); });
  if (plain_word) s[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
  return s;
}

std::string unknown_key_message(std::string_view key, const TableSpec& t) {
  std::string hint = did_you_mean(key, key_names(t));
  if (hint.empty()) {  // a key of another table, or a table, written in the wrong place?
    std::vector<std::string> owners;
    for (const auto& other : schema())
      if (find_key(other, key)) owners.push_back(bracket(other));
    std::vector<std::string> what;
    if (!owners.empty()) what.push_back("a key of " + join(owners, " and "));
    if (const TableSpec* table = find_table(key)) what.push_back("the name of a table, " + bracket(*table));
    if (!what.empty()) hint = fmt::format("; '{}' is {}", key, join(what, " and "));
  }
  return fmt::format("unknown key '{}' in {}{} (allowed: {})", key, bracket(t), hint, join(key_names(t)));
}

std::string count_text(int lo, int hi, std::string_view one, std::string_view many) {
  if (lo == hi) return fmt::format("{} {}", lo, lo == 1 ? one : many);
  if (hi == 0) return fmt::format("at least {} {}", lo, lo == 1 ? one : many);
  if (lo == 0) return fmt::format("at most {} {}", hi, hi == 1 ? one : many);
  return fmt::format("{} {} {} {}", lo, hi == lo + 1 ? "or" : "to", hi, many);
}

std::string unknown_table_message(std::string_view written, std::string_view name) {
  std::vector<std::string> all;
  for (const auto& t : schema()) all.push_back(bracket(t));
  auto best = closest(name, table_names());
  std::string hint = best ? fmt::format("; did you mean {}?", bracket(*find_table(*best))) : "";
  return fmt::format("unknown table {}{} (allowed: {})", written, hint, join(all));
}

bool in_range(const KeySpec& k, double x) {
  if (k.min && (k.min_exclusive ? !(x > *k.min) : !(x >= *k.min))) return false;
  if (k.max && (k.max_exclusive ? !(x < *k.max) : !(x <= *k.max))) return false;
  return true;
}

std::string axes_text(int dim) {
  std::vector<std::string> a(kAxes, kAxes + dim);
  return join(a);
}

std::string toml_quote(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(b, e - b + 1));
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    lines.push_back(l);
  }
  return lines;
}

}  // namespace strata::scene::text
