// `dorado config print odometry|mapper [FILE]`: a settings file as the reader understood it (the
// built-in defaults without FILE); `dorado config keys`: docs/config_keys.md. Both from the
// config structs' field lists, the one place each key and default is written.
#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "config_keys.hpp"
#include "dorado/config/map_config.hpp"
#include "dorado/config/odometry_config.hpp"
#include "one_of.hpp"

namespace dorado::apps {

namespace {

struct ConfigOptions {
    std::string which;
    std::string file;
};

void Print(const ConfigOptions &opt) {  // a bad file throws io::ConfigError: main reports it
    if (opt.which == "odometry") {
        const auto config = opt.file.empty() ? odometry::DopplerOdometryConfig{}
                                             : config::LoadOdometryConfig(opt.file);
        std::cout << config::OdometryConfigYaml(config);
    } else {
        const auto config =
            opt.file.empty() ? config::MapCommandConfig{} : config::LoadMapConfig(opt.file);
        std::cout << config::MapConfigYaml(config);
    }
}

}  // namespace

void RegisterConfigCommand(CLI::App &app) {
    auto *cmd = app.add_subcommand("config", "print settings files and their keys");
    cmd->require_subcommand(1);
    auto opt = std::make_shared<ConfigOptions>();
    auto *print = cmd->add_subcommand(
        "print",
        "a settings file as read (every key, its value and meaning); the built-in defaults "
        "without FILE");
    print->add_option("which", opt->which, "odometry | mapper")
        ->required()
        ->check(OneOf({"odometry", "mapper"}));
    print->add_option("file", opt->file, "an odometry.yaml or mapper.yaml")
        ->check(CLI::ExistingFile);
    print->callback([opt] { Print(*opt); });
    auto *keys = cmd->add_subcommand(
        "keys",
        "every key of odometry.yaml and mapper.yaml with its default (docs/config_keys.md)");
    keys->callback([] { std::cout << ConfigKeysMarkdown(); });
}

}  // namespace dorado::apps
