#include "output_files.hpp"

#include <fmt/format.h>

#include <system_error>

#include <symdyn/detail/writable_path.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::sim {

namespace fs = std::filesystem;

namespace {

std::string kind_of(fs::file_type type) {
  switch (type) {
    case fs::file_type::regular:
      return "a regular file";
    case fs::file_type::directory:
      return "a directory";
    case fs::file_type::symlink:
      return "a symbolic link";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    case fs::file_type::not_found:
      return "missing";
    default:
      return "a special file";
  }
}

}  // namespace

std::string file_kind(const fs::path& path) {
  std::error_code ec;
  return kind_of(fs::status(path, ec).type());
}

void check_output_file(std::string_view option, const fs::path& path) {
  const auto refuse = [&](const std::string& why) {
    throw runtime::OptionError(fmt::format("{} '{}' {}", option, path.string(), why));
  };
  if (path.empty()) refuse("is empty: name a file");
  if (!path.has_filename()) refuse("names a folder: name a file in it");
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::directory) refuse("is a directory: name a file in it");
  if (fs::exists(status)) {
    if (status.type() != fs::file_type::regular) {
      refuse(
          fmt::format("is {}: results are written to regular files only", kind_of(status.type())));
    }
    if (!symdyn::detail::replaceable(path, status.permissions()))
      refuse("is read-only: it is not replaced (make it writable, or name another file)");
  } else if (fs::is_symlink(fs::symlink_status(path, ec))) {
    refuse("is a symbolic link to nothing: name a file");
  }
  // The nearest existing folder: a writable directory.
  const fs::path folder = symdyn::detail::nearest_existing(path.parent_path());
  const fs::file_status f = fs::status(folder, ec);
  if (f.type() != fs::file_type::directory) {
    refuse(fmt::format("cannot be made: '{}' is {}, not a folder", folder.string(),
                       kind_of(f.type())));
  }
  if (!symdyn::detail::can_create_in(folder)) {
    refuse(fmt::format("cannot be written: the folder '{}' is not writable", folder.string()));
  }
}

void create_folders(const fs::path& path) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
}

}  // namespace symdyn::sim
