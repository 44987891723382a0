#pragma once
// OpenCascade's STEP/IGES readers dereference null entities in corrupted files (a misspelled
// entity name such as CARTESIAN_POINTX leaves a reference unresolved, and
// StepGeom_CartesianPoint::NbCoordinates is then called on nothing): the process dies with
// SIGSEGV before any status could be checked. Debian's OCCT is built without signal-to-exception
// conversion, so OCC_CATCH_SIGNALS cannot help; running the same read first in a forked child
// can, whatever the corruption is.
#include <filesystem>
#include <functional>

namespace isospring::geometry::detail {

/// Runs `work` in a forked child process. Returns normally when the child finishes (whether
/// `work` returned or threw: the caller then repeats the work in this process and gets the
/// same result or exception); throws nurbs::InputError naming `file` when the child was killed
/// by a signal. The child's exit is immediate (_exit): no atexit handlers, no stdio flushes.
void fail_if_it_crashes(const std::filesystem::path& file, const std::function<void()>& work);

}  // namespace isospring::geometry::detail
