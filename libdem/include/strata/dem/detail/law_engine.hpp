#pragma once
// Not API: the interface through which the model reaches its pair law's compiled kernels,
// and the registry's row of a law. The law is chosen once, when the model is set up
// (Model<D>::refresh_laws); the model then calls its engine once per step and once per
// probe, never per pair.
#include <strata/dem/detail/model_data.hpp>
#include <strata/dem/material.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace strata::dem::detail {

/// Which pairs LawEngine::pairs lists.
enum class PairSet : std::uint8_t { Bonds, BrokenBonds, Contacts };

/// The pair law's part of a model of dimension D: the step loop and the probes that
/// evaluate pair forces, compiled for one law (step_kernel.hpp).
template <int D>
class LawEngine {
 public:
  virtual ~LawEngine() = default;
  virtual const char* name() const = 0;
  /// Builds the nmat × nmat table of pair laws; pair_materials[a·nmat + b] is the combined
  /// material of materials a and b (the pair rule).
  virtual void set_materials(const std::vector<Material>& pair_materials, int nmat) = 0;
  /// Stiffnesses of the law between materials a and b.
  virtual PairStiffness stiffness(int a, int b) const = 0;
  /// The largest shear displacement an intact bond of any pair law holds without help from
  /// friction or a strength factor (m; the law's intact_shear_reach(), Fs0/Ks for the
  /// solid-lattice law), or 0 where no law says (or none is finite).
  virtual double shear_reach() const = 0;
  /// Whether a step of m runs in lattice slots when the settings allow them (allowed):
  /// what step() decides, and what the thread plan sizes the ranges for.
  virtual bool steps_in_slots(const ModelData<D>& m, bool allowed) const = 0;
  /// One step of the whole model: all pair forces, walls, boundary conditions, the update.
  virtual void step(ModelData<D>& m, const StepCtx& c, bool energy) = 0;
  /// Stored energy of all pairs and walls at the current state, with the increment v·dt the
  /// next step would add, on copies of the pair states.
  virtual double stored_energy(const ModelData<D>& m, const Wall* walls, std::size_t nwalls,
                               double dt) const = 0;
  /// Sum of the internal forces on the particles of a group (same evaluation):
  /// set_in_group[s] says whether the particles of group set s belong to it.
  virtual std::array<double, 3> group_force(const ModelData<D>& m, const Wall* walls, std::size_t nwalls,
                                            double dt, const std::uint8_t* set_in_group) const = 0;
  /// Bonds (all or the broken ones) or contacts with their forces at the current state.
  virtual std::vector<PairView> pairs(const ModelData<D>& m, PairSet which) const = 0;
};

/// Random bond states for the conformance test of a law (tests/dem/test_law_conformance.cpp):
/// each case is a bond between two particles, p (the owner) and j.
struct BondCases {
  Material material;  ///< the bond's (combined) material
  double dt = 0;
  std::int64_t step = 0;  ///< the step number (it seeds the rounding of Us to 32-bit steps)
  int rest = 0;           ///< how the bond pass gets the rest length: 0 radius sum, 1 uniform, 2 per bond
  bool energy = true;     ///< the bond pass also computes energies (as on energy steps)
  std::vector<std::array<double, 3>> xp, xj, vp, vj;  ///< positions and velocities
  std::vector<double> rp, rj;                         ///< radii (all equal for rest = 1)
  std::vector<double> r0, kf, sf;         ///< rest length, stiffness and strength factor (rest = 2)
  std::vector<std::uint8_t> st;           ///< state byte (bond kinds only)
  std::vector<std::array<double, 3>> us;  ///< stored Us (first 1 in 2D)
  /// false: as in a model whose laws all have Ks = 0, which keeps no shear history: the
  /// bond pass holds Us at zero (the cases' us should then be zero)
  bool shear_kept = true;
  std::size_t size() const { return xp.size(); }
};

/// What a path made of each case.
struct BondResults {
  std::vector<std::array<double, 3>> force;  ///< force on p
  std::vector<std::array<double, 3>> us;     ///< new Us
  /// the stored Us before the step as the path holds it (BondShear: an intact bond's in
  /// 32-bit steps)
  std::vector<std::array<double, 3>> us_before;
  /// reference path: 1 when the new Us needed a wide entry the bond did not have (the
  /// bond pass leaves such a bond to the reference kernel, as one that breaks)
  std::vector<std::uint8_t> widened;
  std::vector<std::uint8_t> st;  ///< new state byte
  std::vector<double> energy;    ///< stored energy after the step
  /// reference path: how the bond broke in this step (0, 1 tension, 2 shear); bond pass:
  /// 1 when it left the bond to the reference kernel (its results are then the stored ones)
  std::vector<std::uint8_t> verdict;
};

/// One row of the law registry.
struct LawEntry {
  std::string name, description;
  std::unique_ptr<LawEngine<2>> (*make2)() = nullptr;
  std::unique_ptr<LawEngine<3>> (*make3)() = nullptr;
  /// The cases through the reference kernel as the step's scalar path calls it (dim 2, 3).
  BondResults (*reference)(int dim, const BondCases& cases) = nullptr;
  /// The cases through the bond pass's vectorised chunk function (bond_span).
  BondResults (*batch)(int dim, const BondCases& cases) = nullptr;
  bool has_batch = false;  ///< false: the law has no `lane` and every bond takes `apply`
};

/// Adds a row (register_law.hpp); throws strata::Error (Input) if the name is taken.
void add_law(LawEntry entry);
/// The row of a law by name, or nullptr.
const LawEntry* find_law(std::string_view name);
/// All rows: the built-in laws (kLaws) first, then the registered ones in order.
std::vector<const LawEntry*> all_laws();

}  // namespace strata::dem::detail
