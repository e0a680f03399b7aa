#include "commands.hpp"

namespace dorado::apps {

void AddDatasetChoiceOptions(CLI::App &cmd, io::DatasetChoice &choice) {
    cmd.add_option("--scene", choice.scene,
                   "reader nuscenes: read this scene of the release (e.g. scene-0103) instead of "
                   "the description's nuscenes.scene");
    cmd.add_option("--sequence", choice.sequence,
                   "reader radarscenes: read this sequence (e.g. 105 or sequence_105, a folder "
                   "beside radarscenes.sequence_dir) instead of the description's");
}

}  // namespace dorado::apps
