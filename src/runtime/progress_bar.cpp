#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <string>

#include <symdyn/runtime/progress_bar.hpp>

namespace symdyn::runtime {

namespace {
constexpr auto quiet_period = std::chrono::seconds(1);
constexpr auto redraw_period = std::chrono::milliseconds(100);
constexpr int width = 40;
}  // namespace

ProgressBar::ProgressBar() : ProgressBar(stderr, isatty(STDERR_FILENO) != 0) {}

ProgressBar::ProgressBar(std::FILE* stream, bool terminal)
    : stream_(stream), terminal_(terminal), start_(Clock::now()), last_draw_(start_) {}

ProgressBar::~ProgressBar() {
  finish();
}

ProgressCallback ProgressBar::callback() {
  return [this](double t, double t_begin, double t_end) { update(t, t_begin, t_end); };
}

void ProgressBar::update(double t, double t_begin, double t_end) {
  last_t_ = t;
  if (!terminal_ || finished_) return;
  const auto now = Clock::now();
  if (now - start_ < quiet_period || (drawn_ && now - last_draw_ < redraw_period)) return;
  last_draw_ = now;
  const double span = t_end - t_begin;
  draw(span > 0.0 ? std::clamp((t - t_begin) / span, 0.0, 1.0) : 1.0, t);
}

void ProgressBar::draw(double fraction, double t) {
  const int filled = static_cast<int>(fraction * width);
  fmt::print(stream_, "\r[{}{}] {:3d}%  t = {:.6g}", std::string(filled, '#'),
             std::string(width - filled, ' '), static_cast<int>(fraction * 100.0), t);
  std::fflush(stream_);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (!drawn_) return;
  draw(1.0, last_t_);
  fmt::print(stream_, "\n");
  std::fflush(stream_);
}

}  // namespace symdyn::runtime
