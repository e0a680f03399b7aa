// dorado: Doppler radar odometry and mapping. One program, one subcommand per job.
#include <exception>
#include <iostream>

#include "commands.hpp"
#include "stream_guard.hpp"

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

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError &e) {
        return app.exit(e);
    } catch (const dorado::apps::StoppedEarly &e) {
        std::cerr << "dorado: error: " << e.what() << "\n";
        return e.exit_code();
    } catch (const std::exception &e) {
        std::cerr << "dorado: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
