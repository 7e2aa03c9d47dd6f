// The registry of pair laws: the built-in rows (step.cpp) and the laws programs add with
// register_law() (strata/dem/register_law.hpp). Models look their law up by name when
// they are set up (Model<D>::refresh_laws).
#include <strata/core/error.hpp>
#include <strata/dem/detail/law_engine.hpp>
#include <strata/dem/laws.hpp>

#include <deque>
#include <mutex>

namespace strata::dem {
namespace detail {

std::vector<LawEntry> builtin_law_entries();  // step.cpp

namespace {
// The rows, in a deque so that pointers to them stay valid as rows are added.
struct Registry {
  std::mutex mutex;
  std::deque<LawEntry> rows;
  Registry() {
    for (LawEntry& e : builtin_law_entries()) rows.push_back(std::move(e));
  }
};
Registry& registry() {
  static Registry r;
  return r;
}
}  // namespace

void add_law(LawEntry entry) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const LawEntry& e : r.rows)
    STRATA_CHECK(e.name != entry.name, Input, "register_law: a pair law named '{}' exists already",
                 entry.name);
  r.rows.push_back(std::move(entry));
}

const LawEntry* find_law(std::string_view name) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const LawEntry& e : r.rows)
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<const LawEntry*> all_laws() {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<const LawEntry*> out;
  for (const LawEntry& e : r.rows) out.push_back(&e);
  return out;
}

}  // namespace detail

std::vector<LawInfo> available_laws() {
  std::vector<LawInfo> out;
  for (const detail::LawEntry* e : detail::all_laws())
    out.push_back({e->name.c_str(), e->description.c_str()});
  return out;
}

}  // namespace strata::dem
