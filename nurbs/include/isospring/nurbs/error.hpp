#pragma once
// The one exception type for bad user input across isospring.
//
// Every module throws InputError when a file, a field or a value supplied by the user is wrong.
// The message names where (file, patch, field), what is wrong and how to fix it; the `isospring`
// program prints it and exits with status 1. Programming errors use assertions instead.
#include <stdexcept>
#include <string>

namespace isospring::nurbs {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace isospring::nurbs
