#pragma once
// The files symdyn-sim writes (--out, --html, --glb, --plot, --easyanim,
// --modes), checked before the run: a result goes to a regular file only,
// never over a device, a FIFO, a directory or a read-only file, and not in a
// folder it cannot write. A refusal is an OptionError naming the option and
// the path:
//   --out '/dev/full' is a character device: results are written to regular files only

#include <filesystem>
#include <string>
#include <string_view>

namespace symdyn::sim {

// Throws runtime::OptionError. Missing folders of the path are allowed (the
// run creates them) when the nearest existing one is a writable folder.
void check_output_file(std::string_view option, const std::filesystem::path& path);

// Creates the missing folders of an output path (after check_output_file).
void create_folders(const std::filesystem::path& path);

// What a path is, for messages: "a directory", "a character device", ...
std::string file_kind(const std::filesystem::path& path);

}  // namespace symdyn::sim
