#pragma once
/// @file bench_grid.hpp
/// Parameter grids of a benchmark: dotted keys of the odometry or map config file, each with a
/// list of values. Every point of a grid (one value per key) is a named variant of each method,
/// run with its own config file: the base config with the point's values set.

#include <string>
#include <utility>
#include <vector>

namespace dorado::apps {

/// One key of a grid and the values it takes (YAML scalars, as written in the benchmark file).
struct GridAxis {
    std::string key;  ///< dotted key of the config file, e.g. "mapper.max_iterations"
    std::vector<std::string> values;
};

/// One grid point.
struct GridVariant {
    /// "max_iterations=5,scan_voxel_m=0.5" (last key component = value, in axis order); empty
    /// for the base config when there is no grid.
    std::string name;
    std::vector<std::pair<std::string, std::string>> settings;  ///< (dotted key, value)
};

/// Every point of the grid (the cartesian product, the first axis varying slowest); one unnamed
/// variant without settings when `axes` is empty.
[[nodiscard]] std::vector<GridVariant> GridVariants(const std::vector<GridAxis> &axes);

/// Path of a variant's config file: out_dir/configs/<kind>@<name>.yaml.
[[nodiscard]] std::string VariantConfigPath(const std::string &out_dir, const std::string &kind,
                                            const GridVariant &variant);

/// Writes the variant's config file (atomically): the YAML of `base_config` (none: empty) with
/// every setting of the variant set. Throws std::runtime_error naming the file or the key.
void WriteVariantConfig(const std::string &base_config, const GridVariant &variant,
                        const std::string &path);

}  // namespace dorado::apps
