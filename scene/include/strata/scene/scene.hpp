#pragma once
/// Scene files: declared keys, validation with file:line:col messages, the typed scene.
///
/// Every key a scene may hold is declared once, in the file of its table
/// (scene/src/tables/), with its type, unit, allowed range or choices, default and doc
/// string, next to the function that reads it into the table's struct (description.hpp).
/// The same declarations validate input (files and `--set` overrides) and generate
/// docs/scene-reference.md.
#include <strata/scene/description.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata::scene {

/// Value types a key can have.
enum class Type {
  Bool,
  Integer,
  Real,
  String,
  Choice,       ///< a string from a fixed list
  Path,         ///< a file path, relative to the scene file, that must exist
  OutputPath,   ///< a path, relative to the scene file, that need not exist
  RealList,     ///< array of reals (integers accepted); optional fixed length
  IntegerList,  ///< array of integers (reals without a fractional part accepted), e.g. η values
  StringList,
  RealTable,  ///< array of arrays of reals, e.g. polygon vertices or force histories
};

/// One declared key.
struct KeySpec {
  std::string name;
  Type type = Type::Real;
  std::string unit;  ///< "N/m", "s", "" for none
  std::string doc;   ///< one or two sentences
  bool required = false;
  std::string default_value;   ///< TOML text of the default ("" when none or required)
  std::optional<double> min;   ///< numeric lower bound (also applied to list elements)
  std::optional<double> max;   ///< numeric upper bound
  bool min_exclusive = false;  ///< min is a strict bound (> instead of >=)
  bool max_exclusive = false;
  std::vector<std::string> choices;    ///< for Choice and StringList elements (empty: any)
  int length_min = 0, length_max = 0;  ///< for lists; for RealTable, of each row; 0: unbounded
  /// One component per axis: a RealList (or each RealTable row) must have as many entries as
  /// [scene].dimension; a StringList may only name axes of that dimension. List defaults are
  /// written for 3D and cut to the dimension.
  bool per_axis = false;
  bool allow_inf = false;  ///< a Real that accepts `inf` (e.g. "never breaks")
  /// [coupled] keys: the values of [coupled].case the key applies to (empty: every case). The
  /// loader refuses a key given for another case, naming the keys that case takes.
  std::vector<std::string> cases;
  /// For a key whose default depends on other keys (no default_value): the reference's
  /// default column, e.g. "per case: chain6, metamaterial `3`; wave `1`".
  std::string default_note;
};

/// One declared table: a plain table ([solver]) or an array of tables ([[region]]).
struct TableSpec {
  std::string name;
  bool array = false;     ///< written [[name]], any number of entries
  bool required = false;  ///< must appear at least once
  std::string doc;
  std::vector<KeySpec> keys;
};

/// The scene schema: every table and key strata accepts.
const std::vector<TableSpec>& schema();

/// docs/scene-reference.md, generated from schema().
std::string reference_markdown();

/// Text shared by error messages and the reference (schema.cpp).
/// "> 0", ">= 0 and < 1", "2 or 3"; "" when the key has no numeric bounds.
std::string range_text(const KeySpec& key);
/// "real", "list of reals", ... as the reference's type column shows it.
std::string type_name(Type type);

/// A validated scene: one typed struct per table (description.hpp).
class Scene {
 public:
  std::filesystem::path file;  ///< the scene file as given
  std::filesystem::path dir;   ///< its directory: paths in the scene are relative to it

  // Plain tables: always present, filled with defaults when not written.
  SceneTable scene;
  SolverTable solver;
  OutputTable output;
  ProbeTable probe;
  // Arrays of tables, in file order (possibly empty).
  std::vector<MaterialTable> materials;
  std::vector<RegionTable> regions;
  std::vector<GroupTable> groups;
  std::vector<BoundaryTable> boundaries;
  std::vector<LoadTable> loads;
  std::vector<WallTable> walls;
  /// A coupled scene (the coupled chains of Li et al. 2023, or the 2D coupled wave of
  /// examples/04_coupled_wave) has a [coupled] table, which describes the whole model, and no
  /// particle or mesh tables ([scene], [[material]], [[region]], ...): of those only the
  /// defaults of the plain tables are here.
  std::optional<CoupledTable> coupled;
  /// A calibration (`strata calibrate`) has a [calibrate] table, which describes the targets and
  /// the lattice; of the other tables it may hold only [scene] and output.directory/render.
  std::optional<CalibrateTable> calibrate;
  /// A network scene has a [network] table, which describes the whole model; of the other
  /// tables it may hold only [solver] and some [output] keys.
  std::optional<NetworkTable> network;
  /// A study has a [study] table, [[vary]] and [[measure]] entries and, of the other tables,
  /// only output.directory and output.render.
  std::optional<StudyTable> study;
  std::vector<VaryTable> vary;
  std::vector<MeasureTable> measures;

  /// A hash of every value but those of [output] and solver.steps, solver.duration and
  /// solver.threads (and of the contents of the files the scene names): a checkpoint
  /// continues only the scene it was taken of.
  std::string fingerprint;
};

/// A table that describes a whole job on its own ([coupled], [calibrate]): the other tables a
/// file holding it may have, and of [output] the keys that apply (the job's files go to
/// output.directory; output.render = false leaves out its plots and pictures).
struct JobTable {
  std::string name;
  std::vector<std::string> besides;      ///< tables allowed besides it
  std::vector<std::string> output_keys;  ///< [output] keys that apply
  std::string kind;                      ///< "a coupled scene"
  std::string what;                      ///< "describes the whole model in [coupled]"
};
const std::vector<JobTable>& job_tables();
/// The [coupled] keys that apply to `case_name` (KeySpec::cases), in schema order.
std::vector<std::string> coupled_case_keys(const std::string& case_name);

/// Reads, validates and returns a scene. `overrides` are "key=value" strings from `--set`,
/// with keys like "solver.dt" or "region.specimen.diameter" / "region[0].diameter"; values
/// are TOML values and are validated exactly like the file. Throws strata::Error (Input)
/// with a "file:line:col: what is wrong and what is allowed" message at the first problem.
Scene load(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});

/// Validates scene text (for tests); `file` is the name used in messages and for paths.
Scene parse(const std::string& text, const std::filesystem::path& file,
            const std::vector<std::string>& overrides = {});

/// What a caller is about to do with a scene, for require_build_parts.
enum class SceneUse {
  Model,  ///< fill and mesh the regions only (`strata mesh`): geometry files, FEM meshes
  Run,    ///< build and run it: also the outputs it asks for (frames, pictures, checkpoints)
};

/// What a scene asks of the optional parts of strata (gmsh, CGAL, HDF5, VTK, rendering),
/// checked against this build before anything is built or written. Throws strata::Error
/// (Input) "file:line:col: ..." at the first key the scene writes that needs a part this
/// build leaves out for `use`, naming the option that turns it on (e.g.
/// -DSTRATA_WITH_GMSH=ON). A key left at its default is never refused: a build without VTK
/// writes no frames, one without rendering draws no pictures (the run says so). Returns
/// `sc`, so that a constructor can check the scene in its initialiser list.
const Scene& require_build_parts(const Scene& sc, SceneUse use = SceneUse::Run);

}  // namespace strata::scene
