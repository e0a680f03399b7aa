#pragma once
/// @file preflight.hpp
/// Checks before work: what a command will read is checked before it empties its --out folder,
/// so that a refused run leaves the folder as it was; what the description leaves to dorado (a
/// recording without a description, a description without a mount) is said out loud.

#include <string>

#include "dorado/io/dataset_config.hpp"

namespace dorado::apps {

/// Opens the dataset (every radar of a radars: list) and reads up to its first readable scan.
/// Throws io::DatasetError naming the source and the first problem when it cannot be opened or
/// when none of its first scans can be read (a field the recording does not have, a folder whose
/// files do not fit folder.columns), adding that @p out_dir was left as it was.
void CheckBeforeWork(const io::DatasetConfig &dataset, const std::string &out_dir);

/// One line on stderr for each thing @p command assumes because the description does not say it:
/// a recording read without a description (the paper's Hugin topic, fields and mount), a
/// description without extrinsics.T_base_radar (the radar at the base origin, unrotated).
void StateAssumptions(const io::DatasetConfig &dataset, const std::string &arg,
                      const std::string &command);

}  // namespace dorado::apps
