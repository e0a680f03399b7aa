// dorado: Doppler radar odometry and mapping. One program, one subcommand per job.
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "dorado/io/closest_name.hpp"
#include "stream_guard.hpp"

namespace {

/// The deepest command the parse reached (`dorado`, `dorado map`, `dorado calibrate rotation`).
const CLI::App &DeepestCommand(const CLI::App &app) {
    const CLI::App *command = &app;
    while (!command->get_subcommands().empty()) command = command->get_subcommands().front();
    return *command;
}

/// "dorado map": the command's words from the program's name on.
std::string CommandPath(const CLI::App &command) {
    const CLI::App *parent = command.get_parent();
    return parent ? CommandPath(*parent) + " " + command.get_name() : command.get_name();
}

/// What the command line says of an argument nobody took: an unknown option (with the closest
/// option of that command), an unknown command (with the closest command), or an extra value.
std::string UnexpectedArgument(const CLI::App &command, const std::string &arg) {
    const std::string help = "; `" + CommandPath(command) + " --help` lists ";
    std::vector<std::string> known;
    if (arg.rfind('-', 0) == 0) {
        for (const CLI::Option *option : command.get_options()) {
            for (const auto &name : option->get_lnames()) known.push_back("--" + name);
            for (const auto &name : option->get_snames()) known.push_back("-" + name);
        }
        const std::string name = arg.substr(0, arg.find('='));  // --key=value
        const std::string closest = dorado::io::ClosestName(name, known);
        return "unknown option '" + name + "'" +
               (closest.empty() ? "" : " (did you mean '" + closest + "'?)") + help + "the options";
    }
    for (const CLI::App *sub : command.get_subcommands([](const CLI::App *) { return true; }))
        known.push_back(sub->get_name());
    if (known.empty()) return "unexpected argument '" + arg + "'" + help + "what it takes";
    const std::string closest = dorado::io::ClosestName(arg, known);
    return "unknown command '" + arg + "'" +
           (closest.empty() ? "" : " (did you mean '" + closest + "'?)") + help + "the commands";
}

/// One line for a command-line error: the argument nobody took, if any, else CLI11's message.
std::string UsageError(const CLI::App &app, const CLI::ParseError &e) {
    for (const CLI::App *command = &DeepestCommand(app); command; command = command->get_parent()) {
        const std::vector<std::string> left = command->remaining();
        if (left.empty()) continue;
        std::string arg = left.front();
        for (const auto &a : left) {
            if (a.rfind('-', 0) == 0) {
                arg = a;
                break;
            }
        }
        return UnexpectedArgument(*command, arg);
    }
    const CLI::App &command = DeepestCommand(app);
    const std::string path = CommandPath(command);
    return (command.get_parent() ? path + ": " : "") + e.what() + "; `" + path +
           " --help` lists the " + (command.get_parent() ? "options" : "commands");
}

/// The command words of the command line checked before CLI11 parses it, so that an unknown
/// command followed by --help (`dorado nosuch --help`) is an error naming the closest command
/// instead of the general help: returns the error, or "" when every command word is known.
std::string UnknownCommandWord(const CLI::App &app, int argc, char **argv) {
    const CLI::App *command = &app;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind('-', 0) == 0) return "";  // options from here on: CLI11 judges them
        const auto subs = command->get_subcommands([](const CLI::App *) { return true; });
        if (subs.empty()) return "";  // the command's own positional arguments
        const CLI::App *next = nullptr;
        for (const CLI::App *sub : subs)
            if (sub->check_name(arg)) next = sub;
        if (!next) return UnexpectedArgument(*command, arg);
        command = next;
    }
    return "";
}

}  // namespace

int main(int argc, char **argv) {
    CLI::App app{
        "dorado: Doppler-radar odometry and mapping (radar-only SLAM front end).\n"
        "Run `dorado COMMAND --help` for the options of a command."};
    app.name("dorado");
    app.require_subcommand(1);
    app.set_version_flag("--version", "dorado 0.1.0");

    dorado::apps::RegisterInfoCommand(app);
    dorado::apps::RegisterOdometryCommand(app);
    dorado::apps::RegisterCalibrateCommand(app);
    dorado::apps::RegisterSimulateCommand(app);
    dorado::apps::RegisterMapCommand(app);
    dorado::apps::RegisterEvalCommand(app);
    dorado::apps::RegisterBenchCommand(app);
    dorado::apps::RegisterTwistCommand(app);
    dorado::apps::RegisterConfigCommand(app);
    dorado::apps::RegisterReplayCommand(app);

    if (const std::string unknown = UnknownCommandWord(app, argc, argv); !unknown.empty()) {
        std::cerr << "dorado: error: " << unknown << "\n";
        return 1;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::RuntimeError &e) {  // a command that has said why and chose its code
        return e.get_exit_code();
    } catch (const CLI::ParseError &e) {
        // --help and --version are "errors" with exit code 0; every real one exits 1.
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
        std::cerr << "dorado: error: " << UsageError(app, e) << "\n";
        return 1;
    } catch (const dorado::apps::StoppedEarly &e) {
        std::cerr << "dorado: error: " << e.what() << "\n";
        return e.exit_code();
    } catch (const std::exception &e) {
        std::cerr << "dorado: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
