#pragma once
/// Named binary arrays for checkpoints.
///
/// A library that can save its state (e.g. `dem::Simulation::save_state`) writes named
/// arrays of a few element types through a StateWriter and reads them back through a
/// StateReader. The libraries do not know the file format: `io` implements both with HDF5
/// (strata/io/checkpoint.hpp), and MemoryState keeps them in memory (tests).
///
/// Names are paths such as "dem/particles/x0"; '/' separates groups. Values round-trip bit
/// for bit. Scalars are arrays of one element; a bool is stored as a UInt8.
#include <strata/core/error.hpp>

#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace strata {

/// Element type of a stored array.
enum class StateType : std::uint8_t { UInt8, UInt32, Int64, Float64 };

/// "uint8", "uint32", "int64", "float64" (for messages).
inline const char* state_type_name(StateType t) {
  switch (t) {
    case StateType::UInt8:
      return "uint8";
    case StateType::UInt32:
      return "uint32";
    case StateType::Int64:
      return "int64";
    case StateType::Float64:
      return "float64";
  }
  return "?";
}

/// The StateType that stores a T (bool is stored as UInt8).
template <typename T>
constexpr StateType state_type_of() {
  if constexpr (std::is_same_v<T, std::uint8_t> || std::is_same_v<T, bool>)
    return StateType::UInt8;
  else if constexpr (std::is_same_v<T, std::uint32_t>)
    return StateType::UInt32;
  else if constexpr (std::is_same_v<T, std::int64_t>)
    return StateType::Int64;
  else {
    static_assert(std::is_same_v<T, double>, "state arrays hold uint8, uint32, int64 or double");
    return StateType::Float64;
  }
}

/// Destination of saved state.
class StateWriter {
 public:
  virtual ~StateWriter() = default;
  /// Stores `count` elements of `type` from `data` under `name` (a name is written once).
  virtual void put_array(const std::string& name, StateType type, const void* data, std::size_t count) = 0;

  template <typename T, typename A = std::allocator<T>>
  void put(const std::string& name, const std::vector<T, A>& values) {
    static_assert(!std::is_same_v<T, bool>, "store vector<bool> as uint8");
    put_array(name, state_type_of<T>(), values.data(), values.size());
  }
  template <typename T>
  void put_scalar(const std::string& name, T value) {
    if constexpr (std::is_same_v<T, bool>) {
      const std::uint8_t b = value ? 1 : 0;
      put_array(name, StateType::UInt8, &b, 1);
    } else {
      put_array(name, state_type_of<T>(), &value, 1);
    }
  }
  void put_string(const std::string& name, std::string_view s) {
    put_array(name, StateType::UInt8, s.data(), s.size());
  }
};

/// Source of saved state. Missing names and type mismatches throw strata::Error (IO).
class StateReader {
 public:
  virtual ~StateReader() = default;
  virtual bool has(const std::string& name) const = 0;
  /// Number of elements stored under `name`; throws when it is missing or of another type.
  virtual std::size_t count(const std::string& name, StateType type) const = 0;
  /// Reads exactly `count` elements (as given by count()) into `data`.
  virtual void get_array(const std::string& name, StateType type, void* data, std::size_t count) const = 0;

  template <typename T>
  std::vector<T> get(const std::string& name) const {
    std::vector<T> out;
    get_into(name, out);
    return out;
  }
  /// Like get(), into an array of any allocator.
  template <typename T, typename A>
  void get_into(const std::string& name, std::vector<T, A>& out) const {
    static_assert(!std::is_same_v<T, bool>, "read vector<bool> as uint8");
    out.resize(count(name, state_type_of<T>()));
    get_array(name, state_type_of<T>(), out.data(), out.size());
  }
  /// Like get(), and checks the number of elements.
  template <typename T>
  std::vector<T> get(const std::string& name, std::size_t expected) const {
    std::vector<T> out = get<T>(name);
    STRATA_CHECK(out.size() == expected, IO, "state array '{}' has {} elements, expected {}", name,
                 out.size(), expected);
    return out;
  }
  template <typename T>
  T get_scalar(const std::string& name) const {
    using S = std::conditional_t<std::is_same_v<T, bool>, std::uint8_t, T>;
    const std::vector<S> v = get<S>(name, 1);
    if constexpr (std::is_same_v<T, bool>)
      return v[0] != 0;
    else
      return v[0];
  }
  std::string get_string(const std::string& name) const {
    const std::vector<std::uint8_t> v = get<std::uint8_t>(name);
    return std::string(v.begin(), v.end());
  }
};

/// State kept in memory: a writer and a reader of the same arrays (tests, in-process copies).
class MemoryState final : public StateWriter, public StateReader {
 public:
  void put_array(const std::string& name, StateType type, const void* data, std::size_t count) override {
    STRATA_CHECK(!arrays_.count(name), Internal, "state array '{}' written twice", name);
    Entry& e = arrays_[name];
    e.type = type;
    e.count = count;
    e.bytes.resize(count * element_size(type));
    if (count) std::memcpy(e.bytes.data(), data, e.bytes.size());
  }
  bool has(const std::string& name) const override { return arrays_.count(name) > 0; }
  std::size_t count(const std::string& name, StateType type) const override {
    return entry(name, type).count;
  }
  void get_array(const std::string& name, StateType type, void* data, std::size_t count) const override {
    const Entry& e = entry(name, type);
    STRATA_CHECK(count == e.count, Internal, "state array '{}': {} elements asked, {} stored", name, count,
                 e.count);
    if (count) std::memcpy(data, e.bytes.data(), e.bytes.size());
  }
  /// Names stored, sorted.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [name, e] : arrays_) out.push_back(name);
    return out;
  }

  static std::size_t element_size(StateType t) {
    switch (t) {
      case StateType::UInt8:
        return 1;
      case StateType::UInt32:
        return 4;
      case StateType::Int64:
      case StateType::Float64:
        return 8;
    }
    return 1;
  }

 private:
  struct Entry {
    StateType type = StateType::UInt8;
    std::size_t count = 0;
    std::vector<unsigned char> bytes;
  };
  const Entry& entry(const std::string& name, StateType type) const {
    const auto it = arrays_.find(name);
    STRATA_CHECK(it != arrays_.end(), IO, "state array '{}' is missing", name);
    STRATA_CHECK(it->second.type == type, IO, "state array '{}' holds {}, expected {}", name,
                 state_type_name(it->second.type), state_type_name(type));
    return it->second;
  }
  std::map<std::string, Entry> arrays_;
};

}  // namespace strata
