// Writes the HTML viewer of the double pendulum swinging for 2 s, with its two
// modes about the hanging state as further clips: the page the browser test
// (check_viewer.py) opens. Usage: write_pendulum_viewer <file.html>
#include <fmt/format.h>

#include <numbers>

#include "double_pendulum_absolute.hpp"
#include <symdyn/runtime/html_viewer.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/runtime.hpp>
#include <symdyn/runtime/scene.hpp>

using namespace symdyn::runtime;

int main(int argc, char** argv) {
  if (argc != 2) {
    fmt::print(stderr, "usage: {} <file.html>\n", argv[0]);
    return 2;
  }
  MultibodySystem system(Model::from<symdyn_generated::double_pendulum_absolute>());
  Scene scene(system.model());
  scene.add(1, Shape::capsule(0.04, 1.0)
                   .at(Eigen::Isometry3d(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY())))
                   .with({0.85f, 0.3f, 0.1f, 1.0f}));

  Animation motion(system.model());
  TimeSeries series{
      {"t", "theta1", "theta2", "total_energy"}, {{}, {}, {}, {}}, {"s", "rad", "rad", "J"}};
  IntegratorOptions options;
  options.relative_tolerance = options.absolute_tolerance = 1e-9;
  options.output_interval = 0.02;
  options.on_output = [&](const State& s, const Vector&, const Vector&) {
    motion.record(s);
    const double values[] = {s.t, s.q[0], s.q[1], system.energies(s).total()};
    for (std::size_t k = 0; k < series.columns.size(); ++k) series.columns[k].push_back(values[k]);
  };
  make_integrator("dop853", options)->integrate(system, system.initial_state(), 2.0);

  State hanging = system.initial_state();
  hanging.q << -std::numbers::pi / 2, 0;
  const Linearization lin = linearize(system, hanging);
  std::vector<Animation> shapes;
  std::vector<Clip> clips{{"motion", &motion}};
  const std::vector<Mode> m = modes(lin);
  shapes.reserve(m.size());
  for (const Mode& mode : m) {
    shapes.push_back(mode_animation(system, hanging, lin, mode, 0.4));
    clips.push_back({fmt::format("mode {}: {:.3f} Hz, damping {:.3f}", clips.size(),
                                 mode.natural_frequency_hz, mode.damping_ratio),
                     &shapes.back()});
  }
  write_html(argv[1], "double pendulum", scene, clips, series);
}
