// Output checks run before any work (output_guard.hpp).
#include "isospring/io/output_guard.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace fs = std::filesystem;

namespace {
fs::path resolved(const fs::path& path) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal() : canonical;
}

bool same_file(const fs::path& a, const fs::path& b) {
  if (resolved(a) == resolved(b)) return true;
  std::error_code ec;  // hard links: the same inode under two names
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec) && !ec;
}
}  // namespace

void check_outputs_spare_inputs(const std::vector<fs::path>& inputs,
                                const std::vector<fs::path>& outputs) {
  for (const fs::path& output : outputs)
    for (const fs::path& input : inputs)
      if (same_file(output, input))
        throw nurbs::InputError("output '" + output.string() + "' would overwrite the input '" +
                                input.string() + "' (both are '" + resolved(input).string() +
                                "'); choose another output name or folder");
}

void check_writable_folder(const fs::path& folder) {
  fs::path existing = folder.empty() ? fs::path(".") : folder;
  std::error_code ec;
  while (!fs::exists(existing, ec)) {
    const fs::path parent = existing.parent_path();
    existing = parent.empty() || parent == existing ? fs::path(".") : parent;
    if (parent.empty()) break;
  }
  const std::string fix = "; choose an output location you can write to";
  if (!fs::is_directory(existing, ec))
    throw nurbs::InputError("cannot write into '" + folder.string() + "': '" + existing.string() +
                            "' is not a folder" + fix);
  const fs::path probe = existing / (".isospring-write-check-" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) {
    const int error = errno;  // saved before anything else can change it
    throw nurbs::InputError("cannot write into '" + folder.string() + "': " + std::strerror(error) +
                            " (creating a file in '" + existing.string() + "')" + fix);
  }
  ::close(fd);
  fs::remove(probe, ec);
}

}  // namespace isospring::io
