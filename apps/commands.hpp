#pragma once
/// @file commands.hpp
/// Each `dorado` subcommand registers itself on the CLI11 app from its own cmd_*.cpp file.

#include <CLI/CLI.hpp>

#include "dorado/io/dataset_config.hpp"

namespace dorado::apps {

void RegisterInfoCommand(CLI::App &app);
void RegisterMapCommand(CLI::App &app);
void RegisterOdometryCommand(CLI::App &app);
void RegisterCalibrateCommand(CLI::App &app);
void RegisterSimulateCommand(CLI::App &app);
void RegisterEvalCommand(CLI::App &app);
void RegisterBenchCommand(CLI::App &app);
void RegisterTwistCommand(CLI::App &app);
void RegisterConfigCommand(CLI::App &app);
void RegisterReplayCommand(CLI::App &app);  ///< cmd_replay.cpp with Cyclone DDS, else _none

/// How a dataset description's relative paths resolve, for each command's --data help.
inline constexpr const char *kDataOptionHelp =
    "the folder that the dataset description's relative paths are taken from (the data wherever "
    "it lies). Without it: from the description's data_dir: key (itself relative to the "
    "description file), else from the description file's folder. Absolute paths stay as written";

/// --data DIR on a command that reads a dataset description.
inline CLI::Option *AddDataOption(CLI::App *cmd, std::string &data_dir) {
    return cmd->add_option("--data", data_dir, kDataOptionHelp)->type_name("DIR");
}

/// `--scene NAME` (nuScenes) and `--sequence N` (RadarScenes) on a command that reads a dataset:
/// another scene or sequence of the same release than the description's (io::DatasetChoice).
void AddDatasetChoiceOptions(CLI::App &cmd, io::DatasetChoice &choice);

}  // namespace dorado::apps
