// Checkpoint files in HDF5 (see strata/io/checkpoint.hpp).
#include "strata/io/checkpoint.hpp"

#include <fmt/format.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>

#include "atomic_file.hpp"

#if STRATA_WITH_HDF5
#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <cctype>
#include <vector>

namespace strata::io {
namespace fs = std::filesystem;

#if STRATA_WITH_HDF5

namespace {

/// Value of the root attribute "format": what tells a checkpoint from other HDF5 files.
constexpr const char* kFormatName = "strata checkpoint";
/// Format 2: HDF5 1.10 file format (checksummed metadata) and Fletcher32 on every chunk.
constexpr std::int64_t kFormatVersion = 2;

/// Elements per chunk of a data set (at most): 8 MiB of doubles, well under HDF5's 4 GiB
/// limit on a chunk. The verification at opening reads in pieces of this size too.
constexpr hsize_t kChunkElements = hsize_t{1} << 20;

/// Members of a group (and attributes) kept in its object header, at most (HDF5's limit).
constexpr unsigned kMaxCompact = 65535;

/// Groups nested deeper than this are refused (strata writes a few levels).
constexpr int kMaxDepth = 64;

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

/// What HDF5 reported about the call that just failed (read from its error stack, which
/// the next HDF5 call clears): whether a checksum did not match, and the innermost message.
struct Hdf5Failure {
  bool checksum = false;
  std::string detail;
};

Hdf5Failure last_failure() {
  Hdf5Failure f;
  const auto walk = [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
    auto& out = *static_cast<Hdf5Failure*>(data);
    std::string desc = e->desc ? e->desc : "";
    if (desc.empty()) return 0;
    std::string lower = desc;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower.find("checksum") != std::string::npos) out.checksum = true;
    out.detail = std::move(desc);  // walking downward: the last one is where it was detected
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk, &f);
  return f;
}

/// The message for a part of checkpoint `file` that cannot be read.
std::string damage_message(const fs::path& file, const std::string& part, const Hdf5Failure& f) {
  const std::string why =
      f.checksum ? "fails its checksum" : "cannot be read" + (f.detail.empty() ? "" : " (" + f.detail + ")");
  return fmt::format("checkpoint {} is damaged: {} {}; the file changed after it was written", file.string(),
                     part, why);
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

/// Throws unless `obj` has attribute `name`; a header that cannot be read is damage.
void require_attr(hid_t obj, const char* name, const fs::path& file) {
  const htri_t exists = H5Aexists(obj, name);
  if (exists < 0)
    fail(ErrorKind::IO, "{}", damage_message(file, "the header of the root group", last_failure()));
  STRATA_CHECK(exists > 0, IO, "{} is not a strata checkpoint (no attribute '{}')", file.string(), name);
}

std::string get_string_attr(hid_t obj, const char* name, const fs::path& file) {
  require_attr(obj, name, file);
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
  require_attr(obj, name, file);
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  T value{};
  STRATA_CHECK(attr.ok() && H5Aread(attr.get(), type, &value) >= 0, IO, "{}: cannot read attribute '{}'",
               file.string(), name);
  return value;
}

/// Reads every data set of a checkpoint once, so that HDF5 checks every checksum of the file
/// (the metadata ones as it loads object headers and indexes, Fletcher32 on every chunk).
class Verifier {
 public:
  explicit Verifier(const fs::path& file) : file_(file) {}

  /// Empty when every part of the file was read back; else what is damaged.
  std::string run(hid_t root) {
    group(root, "");
    return failed_;
  }

 private:
  void group(hid_t g, const std::string& name) {
    if (depth_ >= kMaxDepth) {
      failed_ = fmt::format("{} is not a strata checkpoint (groups nested deeper than {})", file_.string(),
                            kMaxDepth);
      return;
    }
    const std::string saved = prefix_;
    prefix_ = name;
    ++depth_;
    hsize_t idx = 0;
    const herr_t r = H5Literate(g, H5_INDEX_NAME, H5_ITER_NATIVE, &idx, &Verifier::member, this);
    if (r < 0 && failed_.empty())
      failed_ = damage_message(
          file_, name.empty() ? "the root group's member list" : "the member list of '" + name + "'",
          last_failure());
    --depth_;
    prefix_ = saved;
  }

  static herr_t member(hid_t g, const char* name, const H5L_info_t* info, void* self) {
    auto& v = *static_cast<Verifier*>(self);
    if (info->type != H5L_TYPE_HARD) return 0;  // strata writes none; they hold no data here
    const std::string full = v.prefix_.empty() ? std::string(name) : v.prefix_ + "/" + name;
    Handle obj(H5Oopen(g, name, H5P_DEFAULT), H5Oclose);
    if (!obj.ok()) {
      v.failed_ = damage_message(v.file_, "the header of '" + full + "'", last_failure());
      return -1;
    }
    switch (H5Iget_type(obj.get())) {
      case H5I_GROUP:
        v.group(obj.get(), full);
        break;
      case H5I_DATASET:
        v.dataset(obj.get(), full);
        break;
      default:
        break;
    }
    return v.failed_.empty() ? 0 : -1;
  }

  void dataset(hid_t set, const std::string& name) {
    Handle type(H5Dget_type(set), H5Tclose);
    Handle space(H5Dget_space(set), H5Sclose);
    if (!type.ok() || !space.ok()) {
      failed_ = damage_message(file_, "the header of '" + name + "'", last_failure());
      return;
    }
    const H5T_class_t cls = H5Tget_class(type.get());
    if ((cls != H5T_INTEGER && cls != H5T_FLOAT) || H5Sget_simple_extent_ndims(space.get()) != 1) {
      failed_ = fmt::format("{} is not a strata checkpoint ('{}' is not a 1-D array of numbers)",
                            file_.string(), name);
      return;
    }
    hsize_t dims[1] = {0};
    H5Sget_simple_extent_dims(space.get(), dims, nullptr);
    const std::size_t size = H5Tget_size(type.get());
    for (hsize_t start = 0; start < dims[0]; start += kChunkElements) {
      const hsize_t n = std::min(kChunkElements, dims[0] - start);
      scratch_.resize(std::max<std::size_t>(scratch_.size(), n * size));
      Handle mem(H5Screate_simple(1, &n, nullptr), H5Sclose);
      const bool ok = mem.ok() &&
                      H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, &start, nullptr, &n, nullptr) >= 0 &&
                      H5Dread(set, type.get(), mem.get(), space.get(), H5P_DEFAULT, scratch_.data()) >= 0;
      if (!ok) {
        failed_ = damage_message(file_, "data set '" + name + "'", last_failure());
        return;
      }
    }
  }

  fs::path file_;
  std::string prefix_;
  std::string failed_;
  int depth_ = 0;
  std::vector<unsigned char> scratch_;
};

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
  // the 1.10 file format: the superblock, the object headers (with the attributes and the
  // group members) and the chunk indexes all carry checksums
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  STRATA_CHECK(fapl.ok() && H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V110, H5F_LIBVER_LATEST) >= 0, IO,
               "cannot create checkpoint {}: this HDF5 library cannot write the 1.10 file format",
               impl_->tmp.string());
  // every group keeps its member list in its object header, and the root group its
  // attributes, rather than in heaps and B-trees whose nodes have bytes outside any checksum
  // (groups made on the way inherit this from the root group)
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  STRATA_CHECK(fcpl.ok() && H5Pset_link_phase_change(fcpl.get(), kMaxCompact, kMaxCompact) >= 0 &&
                   H5Pset_attr_phase_change(fcpl.get(), kMaxCompact, kMaxCompact) >= 0,
               IO, "cannot create checkpoint {}: HDF5 refuses the group settings", impl_->tmp.string());
  impl_->file = H5Fcreate(impl_->tmp.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get());
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
  // chunked with a Fletcher32 checksum on every chunk; an empty array has no data to protect
  // (and a chunk cannot be empty), so it stays contiguous
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (count > 0) {
    const hsize_t chunk[1] = {std::min<hsize_t>(dims[0], kChunkElements)};
    STRATA_CHECK(dcpl.ok() && H5Pset_chunk(dcpl.get(), 1, chunk) >= 0 && H5Pset_fletcher32(dcpl.get()) >= 0,
                 IO, "cannot set up '{}' in checkpoint {} (no Fletcher32 filter in this HDF5?)", name,
                 impl_->tmp.string());
  }
  Handle set(H5Dcreate2(impl_->file, name.c_str(), native_type(type), space.get(), impl_->lcpl, dcpl.get(),
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
  if (impl_->file < 0) {
    const Hdf5Failure f = last_failure();
    if (f.checksum) fail(ErrorKind::IO, "{}", damage_message(path_, "its superblock or root group", f));
    fail(ErrorKind::IO, "cannot open checkpoint {} (damaged, or not a checkpoint){}", path_.string(),
         f.detail.empty() ? "" : ": " + f.detail);
  }
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
  // every checksum is checked now, before the caller uses or writes anything
  const std::string damaged = Verifier(path_).run(root);
  STRATA_CHECK(damaged.empty(), IO, "{}", damaged);
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
