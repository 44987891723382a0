#pragma once
// Checks every command runs before any work, so a bad output location fails in a second rather
// than after the computation, and an input is never overwritten by an output.
#include <filesystem>
#include <vector>

namespace isospring::io {

/// Throws nurbs::InputError naming both paths when an output a command will write (reports
/// included) is one of its inputs: paths are compared after weakly_canonical (so "./a.json",
/// "dir/../a.json" and a symlink to a.json are all a.json), and existing files also by identity
/// (hard links). Call it with every file the command reads and every file it writes.
void check_outputs_spare_inputs(const std::vector<std::filesystem::path>& inputs,
                                const std::vector<std::filesystem::path>& outputs);

/// Throws nurbs::InputError (exit status 1) when files cannot be created in `folder`: the
/// nearest existing ancestor must be a folder in which a file can be created (checked by
/// creating and removing a probe file, which also catches read-only file systems and works for
/// root). The folder itself is not created, so a failed run leaves nothing behind.
void check_writable_folder(const std::filesystem::path& folder);

}  // namespace isospring::io
