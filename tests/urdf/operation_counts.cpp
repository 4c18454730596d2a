// Operation counts of the emitted code for each test robot, imported from its
// URDF file and written by hand (robots_by_hand.hpp), for bench/results/urdf_import.md:
//
//   cmake --build build/release --target urdf_operation_counts
//   build/release/tests/urdf/urdf_operation_counts tests/urdf/robots
#include <fmt/format.h>

#include <string>

#include "urdf/robots_by_hand.hpp"
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/urdf.hpp>

namespace {

using namespace symdyn;

void print_row(const std::string& what, const model::Model& m) {
  const codegen::GeneratedCode code = codegen::generate(m, "default", "counted");
  std::string counts;
  for (const auto& f : code.functions) {
    if (f.name == "positions" || f.name == "velocities" || f.name == "mass_matrix" ||
        f.name == "bias_forces") {
      counts += fmt::format(" | {}", f.operations.total());
    }
  }
  fmt::print("| {} | {}{} |\n", what, code.source.size(), counts);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    fmt::print(stderr, "usage: {} <directory of the test robots>\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  using namespace symdyn::testing::urdf;
  fmt::print(
      "| robot | source bytes | positions | velocities | mass_matrix | bias_forces "
      "|\n|---|---|---|---|---|---|\n");
  print_row("two_link_arm, imported", model::import_urdf_file(dir + "/two_link_arm.urdf").model);
  print_row("two_link_arm, by hand", two_link_arm_by_hand());
  print_row("mobile_base, imported", model::import_urdf_file(dir + "/mobile_base.urdf").model);
  print_row("mobile_base, by hand", mobile_base_by_hand());
  print_row("six_dof_arm, imported", model::import_urdf_file(dir + "/six_dof_arm.urdf").model);
  print_row("six_dof_arm, by hand", six_dof_arm_by_hand());
  return 0;
}
