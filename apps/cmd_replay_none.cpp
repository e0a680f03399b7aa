// `dorado replay` without Cyclone DDS (cyclonedds-dev, cyclonedds-tools absent at configure time,
// or DORADO_WITH_DDS=OFF): the command says so.
#include <cstdio>

#include "commands.hpp"

namespace dorado::apps {

void RegisterReplayCommand(CLI::App &app) {
    auto *cmd = app.add_subcommand("replay", "Publish a rosbag2 recording on DDS (not built here)");
    cmd->allow_extras();
    cmd->callback([]() {
        std::fprintf(stderr,
                     "dorado replay: error: dorado was built without Cyclone DDS (install "
                     "cyclonedds-dev cyclonedds-tools, scripts/setup, and rebuild)\n");
        throw CLI::RuntimeError(1);
    });
}

}  // namespace dorado::apps
