#pragma once
// Runs the tvid binary as a user would and captures what it prints.

#include <string>
#include <vector>

namespace tvid::test {

struct RunResult {
    int exit_code = -1;
    std::string out;  ///< stdout
    std::string err;  ///< stderr
};

/// The tvid binary the tests run: $TVID_BINARY when set (the sanitizer stage runs the release
/// tree's test driver on its own instrumented tvid), else the one built beside the tests.
const std::string& tvid_binary();

/// How many times longer a run of that binary takes than in an optimized build:
/// $TVID_TEST_TIME_SCALE when set (8 under the sanitizers, whose library is compiled at -O1), else 1. Tests that signal a run
/// after some seconds of work, or bound how long it may take, scale those seconds by it.
double test_time_scale();

/// Runs `tvid args...` in folder `cwd` (empty: the current one), no shell involved.
RunResult run_tvid(const std::vector<std::string>& args, const std::string& cwd = "");

/// `tvid args...` started in the background (stdout and stderr to files, stdin from
/// /dev/null), to signal it while it runs. The destructor kills it if it is still running.
class TvidProcess {
public:
    explicit TvidProcess(const std::vector<std::string>& args, const std::string& cwd = "");
    ~TvidProcess();
    TvidProcess(const TvidProcess&) = delete;
    TvidProcess& operator=(const TvidProcess&) = delete;

    int pid() const { return pid_; }
    void send(int signal) const;
    /// Waits at most `seconds` for the exit. false when it is still running.
    bool wait(double seconds);
    /// After wait() returned true: exit status (128 + signal when killed), stdout, stderr.
    const RunResult& result() const { return result_; }

private:
    int pid_ = -1;
    bool exited_ = false;
    std::string out_path_, err_path_;
    RunResult result_;
};

/// Where the terminal is for run_tvid_on_terminal.
enum class TerminalStreams {
    both,         ///< stdout and stderr are the terminal: everything lands in `out`
    stderr_only,  ///< stdout goes to a file (as in `tvid … | tee`): `out` is stdout, `err` the terminal
};

/// Runs `tvid args...` on a pseudo-terminal (forkpty), as a user at a terminal would.
/// The terminal's output is captured as written, escape sequences included.
RunResult run_tvid_on_terminal(const std::vector<std::string>& args, TerminalStreams streams = TerminalStreams::both);

}  // namespace tvid::test
