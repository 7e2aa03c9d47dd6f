#pragma once
// Internal: text of the loader's messages (loader.cpp, checks.cpp): names, suggestions for
// misspellings, counts and ranges.
#include <strata/scene/scene.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace strata::scene::text {

/// Lower-case ASCII copy.
std::string lower(std::string_view s);
/// Optimal-string-alignment (Damerau-Levenshtein) distance, case-insensitive.
std::size_t edit_distance(std::string_view a_in, std::string_view b_in);
/// One word is the other plus a "_suffix" ("kn_typo" and "kn", "tensile" and "tensile_strength").
bool underscore_prefix(std::string_view word, std::string_view cand);
/// The candidate closest to `word`, when close enough to be a likely misspelling.
std::optional<std::string> closest(std::string_view word, const std::vector<std::string>& candidates);
/// "; did you mean 'dt'?" for the closest candidate, or "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates,
                         const char* quote = "'");
std::string join(const std::vector<std::string>& items, std::string_view sep = ", ");
/// "[solver]" or "[[region]]".
std::string bracket(const TableSpec& t);
std::vector<std::string> key_names(const TableSpec& t);
std::vector<std::string> table_names();
/// The declared table or key of that name, or null.
const TableSpec* find_table(std::string_view name);
const KeySpec* find_key(const TableSpec& t, std::string_view name);
/// " (N/m)", or "" for a key without a unit.
std::string unit_suffix(const KeySpec& k);
/// What a key is, for "(...)" in messages: the doc's first sentence without "; required when ..."
/// (the message says that) and with "The" lower-cased ("the material name").
std::string first_sentence(const std::string& doc);
/// "unknown key 'dtt' in [solver]; did you mean 'dt'? (allowed: ...)".
std::string unknown_key_message(std::string_view key, const TableSpec& t);
/// "2", "at least 1", "2 or 3", "1 to 3", with the noun in the right number.
std::string count_text(int lo, int hi, std::string_view one, std::string_view many);
/// `written` is the table as the user wrote it ("[solvr]"), `name` its bare name.
std::string unknown_table_message(std::string_view written, std::string_view name);
/// Whether `x` lies within the key's declared bounds.
bool in_range(const KeySpec& k, double x);
/// "x, y" for 2D.
std::string axes_text(int dim);
/// A TOML string literal of `s`.
std::string toml_quote(std::string_view s);
/// `s` without leading and trailing white space.
std::string trim(std::string_view s);
/// The lines of `text`, without line ends.
std::vector<std::string> split_lines(const std::string& text);

}  // namespace strata::scene::text
