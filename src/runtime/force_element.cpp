#include <fmt/format.h>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/force_element.hpp>

namespace symdyn::runtime {

void check_law_derivatives(const std::string& element, const State& s,
                           const Eigen::Ref<const Matrix>& dQ_dq,
                           const Eigen::Ref<const Matrix>& dQ_dqd, Eigen::Index rows,
                           Eigen::Index cols) {
  for (const auto& [what, d] : {std::pair{"q", &dQ_dq}, std::pair{"qd", &dQ_dqd}}) {
    if (d->rows() != rows || d->cols() != cols) {
      throw ModelError(fmt::format(
          "{}: its law's derivatives with respect to {} were resized to {} x {}; expected {} x {}",
          element, what, d->rows(), d->cols(), rows, cols));
    }
    if (!d->allFinite()) {
      throw NumericError(
          fmt::format("t = {}: {}: its law's derivatives with respect to {} are not finite", s.t,
                      element, what));
    }
  }
}

}  // namespace symdyn::runtime
