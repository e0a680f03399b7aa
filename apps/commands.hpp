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

/// `--scene NAME` (nuScenes) and `--sequence N` (RadarScenes) on a command that reads a dataset:
/// another scene or sequence of the same release than the description's (io::DatasetChoice).
void AddDatasetChoiceOptions(CLI::App &cmd, io::DatasetChoice &choice);

}  // namespace dorado::apps
