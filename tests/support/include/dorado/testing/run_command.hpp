#pragma once
// Runs a command line through the shell with stdout and stderr captured in files of a scratch
// folder: the command-line tests' one way to call a built program.

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace dorado::testing {

struct CommandResult {
    int code = -1;  ///< the exit status
    std::string out, err;
};

inline CommandResult RunCommand(const std::string &command_line,
                                const std::filesystem::path &scratch_dir) {
    const std::string out = (scratch_dir / "stdout.txt").string(),
                      err = (scratch_dir / "stderr.txt").string();
    const int status = std::system((command_line + " > " + out + " 2> " + err).c_str());
    auto slurp = [](const std::string &path) {
        std::stringstream ss;
        ss << std::ifstream(path).rdbuf();
        return ss.str();
    };
    return {WEXITSTATUS(status), slurp(out), slurp(err)};
}

}  // namespace dorado::testing
