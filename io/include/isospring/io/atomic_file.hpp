#pragma once
// Outputs are written atomically: to a temporary file beside the target, then renamed over it,
// so a crash or a full disk never leaves a half-written file where a user expects a good one.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>

namespace isospring::io {

/// Writes `content` to `path` atomically; creates missing parent folders. Throws
/// nurbs::InputError naming the path when it cannot be written.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Streams into a temporary file through `writer`, then renames it to `path`.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& writer);

/// For writers that need a file name (VTK, OpenCascade): `writer` writes to the temporary path it
/// is given, which is then renamed to `path`.
void write_via_temporary(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path&)>& writer);

/// Reads a whole text file; throws InputError naming the file when it is missing or unreadable.
std::string read_text_file(const std::filesystem::path& path, const std::string& what = "file");

}  // namespace isospring::io
