#include <strata/core/parallel.hpp>
#include <strata/fem/assembly.hpp>
#include <strata/fem/element.hpp>

#include <vector>

namespace strata::fem {

Assembled assemble(const Mesh& mesh) {
  mesh.validate();
  const std::size_t ndof = mesh.dofs();
  const int dim = mesh.dim;
  Assembled out;
  out.mass = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(ndof));

  // Slot of each block's first element in the triplet array.
  std::size_t total = 0;
  std::vector<std::size_t> first(mesh.blocks.size());
  for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
    first[b] = total;
    const std::size_t nd = static_cast<std::size_t>(nodes_per_element(mesh.blocks[b].type) * dim);
    total += mesh.blocks[b].size() * nd * nd;
  }
  std::vector<Eigen::Triplet<double>> trip(total);
  // Lumped element masses: per element node, gathered serially below in element order.
  std::vector<std::vector<double>> emass(mesh.blocks.size());

  for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
    const ElementBlock& blk = mesh.blocks[b];
    const int npe = nodes_per_element(blk.type);
    const std::size_t nd = static_cast<std::size_t>(npe * dim);
    emass[b].assign(blk.size() * static_cast<std::size_t>(npe), 0.0);
    std::vector<char> bad(blk.size(), 0);  // exceptions may not leave a parallel region
    // each element writes its own nd² triplets: no sharing, any thread count gives the same array
    par::parallel_for(static_cast<std::ptrdiff_t>(blk.size()), [&](std::ptrdiff_t ei) {
      const auto e = static_cast<std::size_t>(ei);
      ElementMatrices em;
      try {
        element_matrices(mesh, blk, e, em);
      } catch (...) {
        bad[e] = 1;
        return;
      }
      Eigen::Triplet<double>* t = trip.data() + first[b] + e * nd * nd;
      for (std::size_t i = 0; i < nd; ++i) {
        const auto gi = static_cast<int>(static_cast<std::size_t>(em.node[i / dim]) * dim + i % dim);
        for (std::size_t j = 0; j < nd; ++j) {
          const auto gj = static_cast<int>(static_cast<std::size_t>(em.node[j / dim]) * dim + j % dim);
          *t++ = Eigen::Triplet<double>(gi, gj, em.K[i][j]);
        }
      }
      for (int a = 0; a < npe; ++a) emass[b][e * npe + a] = em.m[a];
    });
    for (std::size_t e = 0; e < blk.size(); ++e)
      if (bad[e]) {  // redo the first bad element serially: it throws the error
        ElementMatrices em;
        element_matrices(mesh, blk, e, em);
      }
  }
  out.K.resize(static_cast<Eigen::Index>(ndof), static_cast<Eigen::Index>(ndof));
  out.K.setFromTriplets(trip.begin(), trip.end());  // duplicates summed in list order
  out.K.makeCompressed();

  for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
    const ElementBlock& blk = mesh.blocks[b];
    for (std::size_t k = 0; k < blk.conn.size(); ++k)
      for (int c = 0; c < dim; ++c) out.mass[blk.conn[k] * dim + c] += emass[b][k];
  }
  for (std::size_t i = 0; i < mesh.point_mass.size(); ++i)
    for (int c = 0; c < dim; ++c) out.mass[static_cast<Eigen::Index>(i * dim + c)] += mesh.point_mass[i];
  return out;
}

}  // namespace strata::fem
