#pragma once
// Whether this process may write where it is told to, asked before any long
// work: the generator's --out (codegen) and symdyn-sim's output files
// (apps/sim), which do not depend on each other. Header-only, std and POSIX.

#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace symdyn::detail {

// `start` or its nearest ancestor that exists; "." (relative) or the root
// (absolute) when none of the named ones does.
inline std::filesystem::path nearest_existing(const std::filesystem::path& start) {
  std::error_code ec;
  std::filesystem::path folder = start;
  while (!folder.empty() && !std::filesystem::exists(folder, ec)) folder = folder.parent_path();
  if (!folder.empty()) return folder;
  return start.is_absolute() ? start.root_path() : std::filesystem::path(".");
}

// A file can be made in the existing folder: tried, since root passes access()
// in /proc or on a read-only mount.
inline bool can_create_in(const std::filesystem::path& folder) {
  if (::access(folder.c_str(), W_OK | X_OK) != 0) return false;
  std::string probe = (folder / ".symdyn-probe-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) return false;
  ::close(fd);
  ::unlink(probe.c_str());
  return true;
}

// An existing file this process may replace: access() grants it and (root
// writes anywhere) its permissions mark it writable.
inline bool replaceable(const std::filesystem::path& file, std::filesystem::perms permissions) {
  using std::filesystem::perms;
  constexpr perms any_write = perms::owner_write | perms::group_write | perms::others_write;
  return ::access(file.c_str(), W_OK) == 0 && (permissions & any_write) != perms::none;
}

}  // namespace symdyn::detail
