#include <fmt/format.h>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/relative_motion.hpp>

namespace symdyn::runtime {
namespace {

using Map3 = Eigen::Map<Vec3>;
using MapR = Eigen::Map<RowMat3>;

// Bodies in an order where each comes after its reference.
std::vector<int> references_first(const std::vector<int>& reference) {
  const int n = static_cast<int>(reference.size());
  std::vector<int> order;
  std::vector<char> state(n, 0);  // 0 unvisited, 1 on the path, 2 ordered
  for (int start = 0; start < n; ++start) {
    std::vector<int> path;
    for (int i = start; i >= 0 && state[i] != 2; i = reference[i]) {
      if (reference[i] < -1 || reference[i] >= n) {
        throw ModelError(
            fmt::format("relative motion: body {} has reference {}, not a body", i, reference[i]));
      }
      if (state[i] == 1)
        throw ModelError(fmt::format("relative motion: body {} is relative to itself", i));
      state[i] = 1;
      path.push_back(i);
    }
    for (auto it = path.rbegin(); it != path.rend(); ++it) {
      state[*it] = 2;
      order.push_back(*it);
    }
  }
  return order;
}

}  // namespace

RelativeMotion::RelativeMotion(std::vector<int> reference_body, int nq)
    : reference_(std::move(reference_body)),
      order_(references_first(reference_)),
      nq_(nq),
      relative_(nq, static_cast<int>(reference_.size()), 0) {}

void RelativeMotion::compose(Kinematics& k, bool partials) const {
  for (int i : order_) {
    MapR R(k.R_data() + 9 * i);
    Map3 x(k.x_data() + 3 * i), v(k.v_data() + 3 * i), w(k.w_data() + 3 * i), a(k.a_data() + 3 * i),
        dw(k.dw_data() + 3 * i);
    const Kinematics& l = relative_;
    const auto R_rel = l.R(i);
    const auto x_rel = l.x(i), v_rel = l.v(i), w_rel = l.w(i), a_rel = l.a(i), dw_rel = l.dw(i);
    const int b = reference_[i];
    if (b < 0) {
      R = R_rel, x = x_rel, v = v_rel, w = w_rel, a = a_rel, dw = dw_rel;
      if (partials) {
        for (int j = 0; j < nq_; ++j) {
          Map3(k.dv_dqd_data() + 3 * (i * nq_ + j)) = l.dv_dqd(i, j);
          Map3(k.dw_dqd_data() + 3 * (i * nq_ + j)) = l.dw_dqd(i, j);
        }
      }
      continue;
    }
    const Mat3 RB = k.R(b);
    const Vec3 wB = k.w(b), dwB = k.dw(b);
    const Vec3 r = RB * x_rel;
    const Vec3 w_in_global = RB * w_rel;
    const Vec3 v_in_global = RB * v_rel;
    R = RB * R_rel;
    x = k.x(b) + r;
    w = wB + w_in_global;
    v = k.v(b) + wB.cross(r) + v_in_global;
    a = k.a(b) + dwB.cross(r) + wB.cross(wB.cross(r)) + 2.0 * wB.cross(v_in_global) + RB * a_rel;
    dw = dwB + wB.cross(w_in_global) + RB * dw_rel;
    if (!partials) continue;
    for (int j = 0; j < nq_; ++j) {
      const std::size_t at = 3 * (static_cast<std::size_t>(i) * nq_ + j);
      const Vec3 dv_j = k.dv_dqd(b, j) + k.dw_dqd(b, j).cross(r) + RB * l.dv_dqd(i, j);
      const Vec3 dw_j = k.dw_dqd(b, j) + RB * l.dw_dqd(i, j);
      Map3(k.dv_dqd_data() + at) = dv_j;
      Map3(k.dw_dqd_data() + at) = dw_j;
    }
  }
}

}  // namespace symdyn::runtime
