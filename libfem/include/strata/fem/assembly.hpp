#pragma once
/// Global stiffness (Eigen sparse, compressed rows) and lumped mass of a mesh.
///
/// Assembly is parallel and deterministic: each element's triplets are computed in
/// parallel into its own slot of one array, then a single setFromTriplets in element order
/// sums duplicates in a fixed order — the same matrix, bit for bit, for any thread count.
#include <strata/fem/mesh.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace strata::fem {

/// Compressed sparse row matrix (CSR) used for K.
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// K and the lumped (diagonal) mass, one entry per DOF.
struct Assembled {
  SparseMatrix K;
  Eigen::VectorXd mass;  ///< lumped mass per DOF: element shares + point masses (kg)
};

/// Assembles K and the lumped mass of `mesh` (validated first).
Assembled assemble(const Mesh& mesh);

}  // namespace strata::fem
