// The progress bar draws only on a terminal and only after a second.

#include <catch2/catch.hpp>
#include <cstdio>
#include <string>
#include <thread>

#include <symdyn/runtime/progress_bar.hpp>

namespace {

using symdyn::runtime::ProgressBar;

std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  for (int c; (c = std::fgetc(f)) != EOF;) s.push_back(static_cast<char>(c));
  return s;
}

TEST_CASE("progress bar: silent when not a terminal or short, drawn after a second", "[progress]") {
  std::FILE* pipe_like = std::tmpfile();
  std::FILE* terminal = std::tmpfile();
  REQUIRE(pipe_like != nullptr);
  REQUIRE(terminal != nullptr);
  {
    ProgressBar quiet(pipe_like, false);
    ProgressBar bar(terminal, true);
    auto callback = bar.callback();
    callback(0.5, 0.0, 2.0);
    quiet.update(0.5, 0.0, 2.0);
    CHECK_FALSE(bar.drawn());  // within the first second
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    callback(0.5, 0.0, 2.0);
    quiet.update(0.5, 0.0, 2.0);
    CHECK(bar.drawn());
    CHECK_FALSE(quiet.drawn());
    CHECK(contents(terminal).find(" 25%  t = 0.5") != std::string::npos);
    std::fseek(terminal, 0, SEEK_END);
  }
  CHECK(contents(pipe_like).empty());
  const std::string drawn = contents(terminal);
  CHECK(drawn.find("100%") != std::string::npos);
  CHECK(drawn.back() == '\n');
  std::fclose(pipe_like);
  std::fclose(terminal);
}

}  // namespace
