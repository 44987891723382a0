#include "isospring/io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace fs = std::filesystem;
using nurbs::InputError;

namespace {
fs::path temporary_beside(const fs::path& path) {
  // The pid keeps two concurrent runs writing the same output from clobbering each other's temp.
  std::string name = ".";
  name += path.filename().string();
  name += ".tmp";
  name += std::to_string(::getpid());
  return path.parent_path() / name;
}

void ensure_parent(const fs::path& path) {
  const fs::path parent = path.parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec)
    throw InputError("cannot create folder '" + parent.string() + "': " + ec.message() +
                     "; choose an output location you can write to");
}

void commit(const fs::path& temporary, const fs::path& path) {
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) {
    // Read the reason before the cleanup: removing the temporary with the same error code used
    // to reset it, and the message said "cannot write X: Success".
    const std::string reason = ec.message();
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw InputError("cannot write '" + path.string() + "': " + reason +
                     "; choose an output location you can write to");
  }
}
}  // namespace

void write_file_atomically(const fs::path& path, const std::string& content) {
  write_file_atomically(path, [&](std::ostream& out) { out << content; });
}

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& writer) {
  write_via_temporary(path, [&](const fs::path& temporary) {
    errno = 0;
    std::ofstream out(temporary, std::ios::binary);
    if (!out)
      throw InputError("cannot write '" + path.string() +
                       "': " + (errno ? std::strerror(errno) : "the file cannot be created") +
                       "; choose an output location you can write to");
    writer(out);
    out.flush();
    if (!out) throw InputError("cannot write '" + path.string() + "': write failed (disk full?)");
  });
}

void write_via_temporary(const fs::path& path, const std::function<void(const fs::path&)>& writer) {
  ensure_parent(path);
  const fs::path temporary = temporary_beside(path);
  try {
    writer(temporary);
  } catch (...) {
    std::error_code ec;
    fs::remove(temporary, ec);
    throw;
  }
  if (!fs::exists(temporary))
    throw InputError("cannot write '" + path.string() + "': the writer produced no file");
  commit(temporary, path);
}

std::string read_text_file(const fs::path& path, const std::string& what) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw InputError(what + " '" + path.string() + "' does not exist; check the path");
  if (fs::is_directory(path, ec))
    throw InputError(what + " '" + path.string() + "' is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(what + " '" + path.string() + "' cannot be read (permissions?)");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace isospring::io
