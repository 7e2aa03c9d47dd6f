#pragma once
/// FEM-side partition: a libfem Solver whose external DOFs are prescribed DOFs.
#include <strata/couple/partition.hpp>
#include <strata/fem/solver.hpp>

namespace strata::couple {

class FemPartition final : public Partition {
 public:
  explicit FemPartition(fem::Solver solver, std::string name = "FEM")
      : solver_(std::move(solver)), name_(std::move(name)) {}

  fem::Solver& solver() { return solver_; }
  const fem::Solver& solver() const { return solver_; }

  std::string name() const override { return name_; }
  std::string integrator() const override { return fem::to_string(solver_.settings().scheme); }
  double dt() const override { return solver_.dt(); }
  double time() const override { return solver_.time(); }
  std::size_t dofs() const override { return static_cast<std::size_t>(solver_.u().size()); }
  double displacement(std::size_t d) const override { return solver_.u()[static_cast<Eigen::Index>(d)]; }
  double velocity(std::size_t d) const override { return solver_.v()[static_cast<Eigen::Index>(d)]; }
  void make_external(std::size_t d) override {
    solver_.prescribe(d);
    solver_.mark_exchange(d);  // its work is energy passed between the partitions
  }
  void set_external(std::size_t d, double u, double v) override { solver_.set_prescribed(d, u, v); }
  void initialise() override { solver_.initialise(); }
  void step() override { solver_.step(); }
  double critical_dt() const override { return solver_.stability().dt_crit; }
  double explicit_critical_dt() const override { return solver_.stability().explicit_dt_crit; }
  bool is_explicit() const override { return fem::is_explicit(solver_.settings().scheme); }

 private:
  fem::Solver solver_;
  std::string name_;
};

}  // namespace strata::couple
