#include <symdyn/model/trig_reduction.hpp>

#include <symdyn/symbolic/trig_polynomial.hpp>

namespace symdyn::model {

void reduce_trigonometry(Dynamics& dynamics, const Kinematics& kinematics) {
  std::vector<Expr> outputs = dynamics.mass_matrix;
  outputs.insert(outputs.end(), dynamics.bias.begin(), dynamics.bias.end());
  symbolic::PythagoreanReduction reduced =
      symbolic::reduce_pythagorean(outputs, dynamics.definitions, kinematics.intermediates);
  const std::size_t n = dynamics.mass_matrix.size();
  std::copy(reduced.outputs.begin(), reduced.outputs.begin() + static_cast<std::ptrdiff_t>(n), dynamics.mass_matrix.begin());
  std::copy(reduced.outputs.begin() + static_cast<std::ptrdiff_t>(n), reduced.outputs.end(), dynamics.bias.begin());
  dynamics.definitions = std::move(reduced.definitions);
}

}  // namespace symdyn::model
