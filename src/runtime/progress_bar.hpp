#pragma once
// A progress bar on stderr for long runs:
//
//   ProgressBar bar;
//   options.on_progress = bar.callback();
//   ... integrate ...
//   bar.finish();
//
// It draws only when stderr is a terminal and the run has lasted more than a
// second (short runs and redirected output stay clean), at most ten times a
// second: "[#######             ]  35%  t = 3.5". finish() (or the destructor)
// ends the line if anything was drawn.

#include <chrono>
#include <cstdio>

#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

class ProgressBar {
 public:
  // stream: where to draw (stderr); terminal: whether it is a terminal (default:
  // asks isatty). Both given explicitly only by tests.
  ProgressBar();
  ProgressBar(std::FILE* stream, bool terminal);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Records progress at time t of [t_begin, t_end]; draws if due.
  void update(double t, double t_begin, double t_end);

  // A callback for IntegratorOptions::on_progress; the bar must outlive the run.
  ProgressCallback callback();

  // Draws 100% and ends the line, if the bar was ever drawn.
  void finish();

  bool drawn() const { return drawn_; }

 private:
  using Clock = std::chrono::steady_clock;
  void draw(double fraction, double t);

  std::FILE* stream_;
  bool terminal_;
  Clock::time_point start_;
  Clock::time_point last_draw_;
  bool drawn_ = false;
  bool finished_ = false;
  double last_t_ = 0.0;
};

}  // namespace symdyn::runtime
