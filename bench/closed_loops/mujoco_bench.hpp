#pragma once
// What the closed-loop benchmarks against MuJoCo share: loading an MJCF text,
// CPU time per call, and the settings of MuJoCo's soft equality constraints
// they compare (bench/results/closed_loops.md).
#include <mujoco/mujoco.h>

#include <algorithm>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace symdyn_bench {

// MuJoCo reads MJCF from a file only (2.2): through a temporary one.
inline mjModel* load_mjcf(const std::string& xml, const std::string& name) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("symdyn_" + name + "_mujoco.xml");
  std::ofstream(path) << xml;
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  std::filesystem::remove(path);
  if (m == nullptr) throw std::runtime_error("MuJoCo, " + name + ": " + error);
  return m;
}

inline double cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

// Median over 5 repetitions of the CPU time per call of `call(k)`, k = 0 ... calls - 1.
inline double per_call_ns(const std::function<void(int)>& call, int calls) {
  std::vector<double> times;
  for (int r = 0; r < 5; ++r) {
    const double start = cpu_seconds();
    for (int k = 0; k < calls; ++k) call(k);
    times.push_back((cpu_seconds() - start) / calls * 1e9);
  }
  std::sort(times.begin(), times.end());
  return times[2];
}

// A setting of MuJoCo's soft constraint: its name in the tables and the
// attributes it adds to each equality.
struct ConstraintSetting {
  const char* name;
  std::string attributes;
};

// MuJoCo's default impedance and time constant, an impedance close to rigid,
// and with it the shortest time constant a step of 1 ms allows (2 steps).
inline std::vector<ConstraintSetting> constraint_settings() {
  return {{"default (solimp 0.9 0.95, solref 0.02)", ""},
          {"stiff (solimp 0.9999 0.9999)", R"(solimp="0.9999 0.9999 0.001")"},
          {"stiffest (solimp 0.9999 0.9999, solref 0.002)",
           R"(solimp="0.9999 0.9999 0.001" solref="0.002 1")"}};
}

}  // namespace symdyn_bench
