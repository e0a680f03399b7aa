#pragma once
/// @file require.hpp
/// The one check behind the config structs' Validate(): a message that names the key as the YAML
/// files spell it ("section.key: what"); the config readers make it "FILE: key '...': what".

#include <stdexcept>
#include <string>

namespace dorado {

/// Throws std::invalid_argument("key: what") unless @p ok.
inline void Require(bool ok, const std::string &key, const std::string &what) {
    if (!ok) throw std::invalid_argument(key + ": " + what);
}

}  // namespace dorado
