// Checkpoint files in HDF5 (see strata/io/checkpoint.hpp).
#include "strata/io/checkpoint.hpp"

#include <strata/config.hpp>
#include <strata/core/error.hpp>

#include "atomic_file.hpp"

#if STRATA_WITH_HDF5
#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <vector>

namespace strata::io {
namespace fs = std::filesystem;

#if STRATA_WITH_HDF5

namespace {

/// Value of the root attribute "format": what tells a checkpoint from other HDF5 files.
constexpr const char* kFormatName = "strata checkpoint";
constexpr std::int64_t kFormatVersion = 1;

/// Closes an HDF5 handle when it goes out of scope.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }
  /// Closes now and reports whether that worked.
  bool close() {
    const bool good = id_ < 0 || close_(id_) >= 0;
    id_ = -1;
    return good;
  }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// HDF5 prints its error stack to stderr by default; strata reports errors itself.
void quiet_hdf5() {
  static const bool done = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

hid_t native_type(StateType t) {
  switch (t) {
    case StateType::UInt8:
      return H5T_NATIVE_UINT8;
    case StateType::UInt32:
      return H5T_NATIVE_UINT32;
    case StateType::Int64:
      return H5T_NATIVE_INT64;
    case StateType::Float64:
      return H5T_NATIVE_DOUBLE;
  }
  return H5T_NATIVE_UINT8;
}

/// Whether a stored element type holds values of `t` (class, size and sign).
bool same_kind(hid_t stored, StateType t) {
  const hid_t want = native_type(t);
  if (H5Tget_class(stored) != H5Tget_class(want) || H5Tget_size(stored) != H5Tget_size(want)) return false;
  return H5Tget_class(want) != H5T_INTEGER || H5Tget_sign(stored) == H5Tget_sign(want);
}

void put_string_attr(hid_t obj, const char* name, const std::string& value, const fs::path& file) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), std::max<std::size_t>(1, value.size()));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  const std::string padded = value.empty() ? std::string(1, '\0') : value;
  STRATA_CHECK(attr.ok() && H5Awrite(attr.get(), type.get(), padded.data()) >= 0, IO,
               "cannot write attribute '{}' to {}", name, file.string());
}

template <typename T>
void put_number_attr(hid_t obj, const char* name, T value, hid_t type, const fs::path& file) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  STRATA_CHECK(attr.ok() && H5Awrite(attr.get(), type, &value) >= 0, IO, "cannot write attribute '{}' to {}",
               name, file.string());
}

std::string get_string_attr(hid_t obj, const char* name, const fs::path& file) {
  STRATA_CHECK(H5Aexists(obj, name) > 0, IO, "{} is not a strata checkpoint (no attribute '{}')",
               file.string(), name);
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  Handle stored(H5Aget_type(attr.get()), H5Tclose);
  STRATA_CHECK(stored.ok() && H5Tget_class(stored.get()) == H5T_STRING && !H5Tis_variable_str(stored.get()),
               IO, "{}: attribute '{}' is not a text", file.string(), name);
  const std::size_t size = H5Tget_size(stored.get());
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), size);
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  std::string out(size, '\0');
  STRATA_CHECK(H5Aread(attr.get(), type.get(), out.data()) >= 0, IO, "{}: cannot read attribute '{}'",
               file.string(), name);
  out.resize(out.find('\0') == std::string::npos ? out.size() : out.find('\0'));
  return out;
}

template <typename T>
T get_number_attr(hid_t obj, const char* name, hid_t type, const fs::path& file) {
  STRATA_CHECK(H5Aexists(obj, name) > 0, IO, "{} is not a strata checkpoint (no attribute '{}')",
               file.string(), name);
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  T value{};
  STRATA_CHECK(attr.ok() && H5Aread(attr.get(), type, &value) >= 0, IO, "{}: cannot read attribute '{}'",
               file.string(), name);
  return value;
}

}  // namespace

struct CheckpointWriter::Impl {
  fs::path tmp;
  hid_t file = -1;
  hid_t lcpl = -1;  // link creation: intermediate groups on
  ~Impl() {
    if (lcpl >= 0) H5Pclose(lcpl);
    if (file >= 0) {
      H5Fclose(file);
      std::error_code ec;
      fs::remove(tmp, ec);  // never committed
    }
  }
};

CheckpointWriter::CheckpointWriter(const fs::path& path, const CheckpointInfo& info)
    : path_(path), impl_(std::make_unique<Impl>()) {
  quiet_hdf5();
  detail::make_parent(path_);
  impl_->tmp = detail::temp_path(path_);
  impl_->file = H5Fcreate(impl_->tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  STRATA_CHECK(impl_->file >= 0, IO, "cannot create checkpoint {}", impl_->tmp.string());
  impl_->lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(impl_->lcpl, 1);
  const hid_t root = impl_->file;
  put_string_attr(root, "format", kFormatName, impl_->tmp);
  put_number_attr<std::int64_t>(root, "format_version", kFormatVersion, H5T_NATIVE_INT64, impl_->tmp);
  put_string_attr(root, "strata_version", info.version, impl_->tmp);
  put_string_attr(root, "scene_fingerprint", info.fingerprint, impl_->tmp);
  put_number_attr<std::int64_t>(root, "dimension", info.dimension, H5T_NATIVE_INT64, impl_->tmp);
  put_number_attr<std::uint64_t>(root, "particles", info.particles, H5T_NATIVE_UINT64, impl_->tmp);
  put_number_attr<std::int64_t>(root, "step", info.step, H5T_NATIVE_INT64, impl_->tmp);
  put_number_attr<double>(root, "time", info.time, H5T_NATIVE_DOUBLE, impl_->tmp);
}

CheckpointWriter::~CheckpointWriter() = default;

void CheckpointWriter::put_array(const std::string& name, StateType type, const void* data,
                                 std::size_t count) {
  STRATA_CHECK(impl_->file >= 0, IO, "checkpoint {} is already committed", path_.string());
  const hsize_t dims[1] = {static_cast<hsize_t>(count)};
  Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  Handle set(H5Dcreate2(impl_->file, name.c_str(), native_type(type), space.get(), impl_->lcpl, H5P_DEFAULT,
                        H5P_DEFAULT),
             H5Dclose);
  STRATA_CHECK(space.ok() && set.ok(), IO, "cannot create '{}' in checkpoint {} (written twice?)", name,
               impl_->tmp.string());
  if (count > 0)
    STRATA_CHECK(H5Dwrite(set.get(), native_type(type), H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0, IO,
                 "cannot write '{}' to checkpoint {} (disk full?)", name, impl_->tmp.string());
}

void CheckpointWriter::commit() {
  STRATA_CHECK(impl_->file >= 0, IO, "checkpoint {} is already committed", path_.string());
  const bool flushed = H5Fflush(impl_->file, H5F_SCOPE_GLOBAL) >= 0;
  const bool closed = H5Fclose(impl_->file) >= 0;
  impl_->file = -1;
  // the data must be on disk before the rename makes it the checkpoint
  const int fd = ::open(impl_->tmp.c_str(), O_RDONLY);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  if (fd >= 0) ::close(fd);
  if (!(flushed && closed && synced)) {
    std::error_code ec;
    fs::remove(impl_->tmp, ec);
    fail(ErrorKind::IO, "cannot write checkpoint {} (disk full?)", impl_->tmp.string());
  }
  detail::commit(impl_->tmp, path_);
}

struct CheckpointReader::Impl {
  hid_t file = -1;
  ~Impl() {
    if (file >= 0) H5Fclose(file);
  }
  /// Opens dataset `name`, or throws naming the checkpoint.
  hid_t open(const std::string& name, const fs::path& path) const {
    // H5Lexists needs every group on the way to exist: test them one by one
    for (std::size_t pos = name.find('/');; pos = name.find('/', pos + 1)) {
      const std::string part = name.substr(0, pos);
      STRATA_CHECK(H5Lexists(file, part.c_str(), H5P_DEFAULT) > 0, IO, "checkpoint {} has no '{}'",
                   path.string(), name);
      if (pos == std::string::npos) break;
    }
    const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    STRATA_CHECK(set >= 0, IO, "checkpoint {}: '{}' is not a data set", path.string(), name);
    return set;
  }
};

CheckpointReader::CheckpointReader(const fs::path& path) : path_(path), impl_(std::make_unique<Impl>()) {
  quiet_hdf5();
  STRATA_CHECK(fs::exists(path_), IO, "checkpoint {} not found", path_.string());
  STRATA_CHECK(H5Fis_hdf5(path_.c_str()) > 0, IO, "{} is not a strata checkpoint (not an HDF5 file)",
               path_.string());
  impl_->file = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  STRATA_CHECK(impl_->file >= 0, IO, "cannot open checkpoint {}", path_.string());
  const hid_t root = impl_->file;
  const std::string format = get_string_attr(root, "format", path_);
  STRATA_CHECK(format == kFormatName, IO, "{} is not a strata checkpoint (format '{}')", path_.string(),
               format);
  const auto version = get_number_attr<std::int64_t>(root, "format_version", H5T_NATIVE_INT64, path_);
  STRATA_CHECK(version == kFormatVersion, Input,
               "checkpoint {} has file format {}; this strata reads format {}", path_.string(), version,
               kFormatVersion);
  info_.version = get_string_attr(root, "strata_version", path_);
  info_.fingerprint = get_string_attr(root, "scene_fingerprint", path_);
  info_.dimension =
      static_cast<int>(get_number_attr<std::int64_t>(root, "dimension", H5T_NATIVE_INT64, path_));
  info_.particles = get_number_attr<std::uint64_t>(root, "particles", H5T_NATIVE_UINT64, path_);
  info_.step = get_number_attr<std::int64_t>(root, "step", H5T_NATIVE_INT64, path_);
  info_.time = get_number_attr<double>(root, "time", H5T_NATIVE_DOUBLE, path_);
}

CheckpointReader::~CheckpointReader() = default;

bool CheckpointReader::has(const std::string& name) const {
  for (std::size_t pos = name.find('/');; pos = name.find('/', pos + 1)) {
    if (H5Lexists(impl_->file, name.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
    if (pos == std::string::npos) return true;
  }
}

std::size_t CheckpointReader::count(const std::string& name, StateType type) const {
  Handle set(impl_->open(name, path_), H5Dclose);
  Handle stored(H5Dget_type(set.get()), H5Tclose);
  STRATA_CHECK(stored.ok() && same_kind(stored.get(), type), IO,
               "checkpoint {}: '{}' does not hold {} values", path_.string(), name, state_type_name(type));
  Handle space(H5Dget_space(set.get()), H5Sclose);
  STRATA_CHECK(space.ok() && H5Sget_simple_extent_ndims(space.get()) == 1, IO,
               "checkpoint {}: '{}' is not a 1-D array", path_.string(), name);
  hsize_t dims[1] = {0};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  return static_cast<std::size_t>(dims[0]);
}

void CheckpointReader::get_array(const std::string& name, StateType type, void* data,
                                 std::size_t count) const {
  const std::size_t stored = this->count(name, type);
  STRATA_CHECK(stored == count, IO, "checkpoint {}: '{}' has {} values, {} asked", path_.string(), name,
               stored, count);
  if (count == 0) return;
  Handle set(impl_->open(name, path_), H5Dclose);
  STRATA_CHECK(H5Dread(set.get(), native_type(type), H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0, IO,
               "checkpoint {}: cannot read '{}'", path_.string(), name);
}

#else  // no HDF5 in this build

struct CheckpointWriter::Impl {};
struct CheckpointReader::Impl {};

CheckpointWriter::CheckpointWriter(const fs::path& path, const CheckpointInfo&) : path_(path) {
  fail_missing_feature("STRATA_WITH_HDF5", "checkpoints");
}
CheckpointWriter::~CheckpointWriter() = default;
void CheckpointWriter::put_array(const std::string&, StateType, const void*, std::size_t) {
  fail_missing_feature("STRATA_WITH_HDF5", "checkpoints");
}
void CheckpointWriter::commit() { fail_missing_feature("STRATA_WITH_HDF5", "checkpoints"); }

CheckpointReader::CheckpointReader(const fs::path& path) : path_(path) {
  fail_missing_feature("STRATA_WITH_HDF5", "checkpoints");
}
CheckpointReader::~CheckpointReader() = default;
bool CheckpointReader::has(const std::string&) const {
  fail_missing_feature("STRATA_WITH_HDF5", "checkpoints");
}
std::size_t CheckpointReader::count(const std::string&, StateType) const {
  fail_missing_feature("STRATA_WITH_HDF5", "checkpoints");
}
void CheckpointReader::get_array(const std::string&, StateType, void*, std::size_t) const {
  fail_missing_feature("STRATA_WITH_HDF5", "checkpoints");
}

#endif

}  // namespace strata::io
