// A serial chain of N identical links (docs/models.md 6), for scaling studies:
// one model chain_N per N in {2, 4, 8, 16, 32, 64}, each with the variants
// "relative" (every link relative to the previous one) and "absolute" (every
// link from the ground: the full product of the chain up to it).
#include <fmt/format.h>

#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

constexpr double L = 0.5;

// The joint of link k turns about z, y, x for k mod 3 = 0, 1, 2.
Transform joint(int k, Expr angle) {
  static constexpr Transform (*rotations[])(Expr) = {Trotz, Troty, Trotx};
  return rotations[k % 3](angle);
}

void build(Model& m, std::string_view variant, int n) {
  const auto q = m.coordinates(n, "joint");  // joint0, joint1, ...
  Transform T0G;                             // the product of the chain up to link k
  for (int k = 0; k < n; ++k) {
    const Transform local = k == 0 ? joint(0, q[0]) * Tdisp(L / 2, 0, 0)
                                   : Tdisp(L / 2, 0, 0) * joint(k, q[k]) * Tdisp(L / 2, 0, 0);
    T0G *= local;
    Body& link = m.body(fmt::format("link{}", k))
                     .mass(1.0)
                     .inertia(0.001, 0.020833333333333333, 0.020833333333333333);
    if (k == 0 || variant == "absolute") {
      link.motion(T0G);
    } else {
      link.motion(local).relative_to(fmt::format("link{}", k - 1));
    }
    m.initial(q[k], 0.1);
  }
  m.gravity(0, 0, -9.81);
}

Definition chain(int n) {
  return {fmt::format("chain_{}", n),
          {"relative", "absolute"},
          [n](Model& m, std::string_view variant) { build(m, variant, n); }};
}

const Registration registrations[] = {Registration(chain(2)),  Registration(chain(4)),
                                      Registration(chain(8)),  Registration(chain(16)),
                                      Registration(chain(32)), Registration(chain(64))};

}  // namespace
