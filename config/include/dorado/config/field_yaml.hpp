#pragma once
/// @file field_yaml.hpp
/// The field-list visitors (io/field_yaml.hpp: in dorado_io, which the dataset description's reader
/// shares) under the names the odometry and mapper files' code uses.

#include "dorado/io/field_yaml.hpp"

namespace dorado::config {

using io::FieldLister;
using io::FieldReader;
using io::FieldRow;
using io::FieldWriter;
using io::FormatValue;
using io::KeyError;
using io::ListFields;
using io::MarkdownTable;

}  // namespace dorado::config
