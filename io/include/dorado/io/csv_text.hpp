#pragma once
/// @file csv_text.hpp
/// Text cells of the CSV files dorado writes (RFC 4180): quoted, inner quotes doubled.

#include <string>

namespace dorado::io {

/// @p text as a quoted CSV cell: "a ""b"" c".
[[nodiscard]] inline std::string CsvQuoted(const std::string &text) {
    std::string quoted = "\"";
    for (const char c : text) {
        if (c == '"') quoted += '"';
        quoted += c;
    }
    return quoted + '"';
}

/// @p text as a CSV cell, quoted only when it holds a comma, a quote or a line break.
[[nodiscard]] inline std::string CsvCell(const std::string &text) {
    return text.find_first_of(",\"\r\n") == std::string::npos ? text : CsvQuoted(text);
}

}  // namespace dorado::io
