#pragma once
/// Checkpoint files: the StateWriter/StateReader of strata/core/state_io.hpp in HDF5.
///
/// One HDF5 file per checkpoint. Every state array is a 1-D dataset under its name
/// ("dem/particles/position/x"; '/' makes groups); the root group carries attributes that
/// say what the checkpoint belongs to (CheckpointInfo). A checkpoint is written to
/// `<path>.tmp` and renamed onto `<path>` by commit(), so a run killed while writing leaves
/// the previous checkpoint intact.
///
/// Integrity: a checkpoint is written in the HDF5 1.10 file format, in which the superblock,
/// every object header (these hold the root attributes, each group's list of members and
/// each data set's type, size and layout) and every chunk index carry a checksum (Jenkins
/// lookup3), and every non-empty array is stored in chunks (at most 2^20 elements each) with
/// HDF5's Fletcher32 filter, a checksum of each chunk's bytes; empty arrays have no data.
/// Opening a checkpoint reads every data set once, so every checksum in the file is checked
/// before the caller gets anything: a file changed after it was written (one flipped bit
/// included) is refused with strata::Error (IO) naming the file and the part that fails.
/// Only a change in bytes that HDF5 does not use (free space between objects) passes, and
/// it changes nothing that is read.
///
/// Builds without HDF5 (STRATA_WITH_HDF5 off) throw strata::Error (Unsupported) naming the
/// option from every function here.
#include <strata/core/state_io.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace strata::io {

/// What a checkpoint belongs to (root attributes of the file).
struct CheckpointInfo {
  std::string version;      ///< strata version that wrote it (STRATA_VERSION)
  std::string fingerprint;  ///< fingerprint of the scene it was run from (the driver computes it)
  int dimension = 0;        ///< 2 or 3
  std::uint64_t particles = 0;
  std::int64_t step = 0;
  double time = 0;  ///< simulated time (s)
};

/// Writes a checkpoint to `<path>.tmp`; commit() makes it `<path>`. Destroying a writer
/// that was not committed removes the temporary file.
class CheckpointWriter final : public StateWriter {
 public:
  CheckpointWriter(const std::filesystem::path& path, const CheckpointInfo& info);
  ~CheckpointWriter() override;
  CheckpointWriter(const CheckpointWriter&) = delete;
  CheckpointWriter& operator=(const CheckpointWriter&) = delete;

  void put_array(const std::string& name, StateType type, const void* data, std::size_t count) override;
  /// Flushes and closes the file, then renames it onto the final path.
  void commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  struct Impl;
  std::filesystem::path path_;
  std::unique_ptr<Impl> impl_;
};

/// Reads a checkpoint. Opening fails with strata::Error (IO) when the file is missing, is
/// not a strata checkpoint, or is damaged (some checksum does not match); it reads the whole
/// file once to check that. Checkpoints of another format version are refused (Input).
class CheckpointReader final : public StateReader {
 public:
  explicit CheckpointReader(const std::filesystem::path& path);
  ~CheckpointReader() override;
  CheckpointReader(const CheckpointReader&) = delete;
  CheckpointReader& operator=(const CheckpointReader&) = delete;

  const CheckpointInfo& info() const { return info_; }

  bool has(const std::string& name) const override;
  std::size_t count(const std::string& name, StateType type) const override;
  void get_array(const std::string& name, StateType type, void* data, std::size_t count) const override;

 private:
  struct Impl;
  std::filesystem::path path_;
  CheckpointInfo info_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace strata::io
