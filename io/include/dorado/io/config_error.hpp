#pragma once
/// @file config_error.hpp
/// The one exception type of the configuration readers.

#include <stdexcept>

namespace dorado::io {

/// A bad configuration: the message names the file and the key.
class ConfigError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace dorado::io
