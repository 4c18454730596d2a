// A model file that imports a URDF robot and extends it with the builder
// (docs/urdf.md): the two-link arm carrying a payload on its forearm.
#include <symdyn/model/urdf.hpp>

namespace {

using namespace symdyn::model;

void build(Model& m, std::string_view) {
  add_urdf(m, read_urdf_file(TWO_LINK_ARM_URDF));
  m.body("payload")
      .mass(2.0)
      .inertia(0.01, 0.01, 0.01)
      .relative_to("forearm")
      .motion(Tdisp(0.3, 0, 0));
}

const Registration registration({"arm_with_payload", {"default"}, build});

}  // namespace
