#include "support/run_tvid.hpp"

#include <fcntl.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <thread>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace tvid::test {

const std::string& tvid_binary() {
    static const std::string binary = [] {
        const char* from_environment = std::getenv("TVID_BINARY");
        return std::string(from_environment != nullptr && *from_environment != '\0' ? from_environment : TVID_BINARY);
    }();
    return binary;
}

double test_time_scale() {
    static const double scale = [] {
        const char* from_environment = std::getenv("TVID_TEST_TIME_SCALE");
        if (from_environment == nullptr || *from_environment == '\0') return 1.0;
        char* end = nullptr;
        const double value = std::strtod(from_environment, &end);
        return end != from_environment && *end == '\0' && value >= 1.0 ? value : 1.0;
    }();
    return scale;
}

namespace {
std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

int status_to_exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status); }

// In the child: exec tvid with `args`, or exit 127.
[[noreturn]] void exec_tvid(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    std::string binary = tvid_binary();
    argv.push_back(binary.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
}

// In the child: run in `cwd`, stdin from /dev/null, stdout and stderr to the two files,
// then exec tvid with `args`.
[[noreturn]] void exec_tvid_redirected(const std::vector<std::string>& args, const std::string& cwd,
                                       const std::string& out_path, const std::string& err_path) {
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(127);
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = ::open("/dev/null", O_RDONLY);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    exec_tvid(args);
}

std::string scratch_base() {
    static int counter = 0;
    return (std::filesystem::temp_directory_path() /
            ("tvid-run-" + std::to_string(::getpid()) + "-" + std::to_string(counter++)))
        .string();
}
}  // namespace

RunResult run_tvid(const std::vector<std::string>& args, const std::string& cwd) {
    const std::string base = scratch_base();
    const std::string out_path = base + ".out", err_path = base + ".err";
    RunResult r;
    const pid_t pid = ::fork();
    if (pid == 0) exec_tvid_redirected(args, cwd, out_path, err_path);
    int status = 0;
    ::waitpid(pid, &status, 0);
    r.exit_code = status_to_exit_code(status);
    r.out = slurp(out_path);
    r.err = slurp(err_path);
    std::filesystem::remove(out_path);
    std::filesystem::remove(err_path);
    return r;
}


TvidProcess::TvidProcess(const std::vector<std::string>& args, const std::string& cwd) {
    const std::string base = scratch_base();
    out_path_ = base + ".out";
    err_path_ = base + ".err";
    pid_ = ::fork();
    if (pid_ == 0) exec_tvid_redirected(args, cwd, out_path_, err_path_);
}

TvidProcess::~TvidProcess() {
    if (pid_ > 0 && !exited_) {
        ::kill(pid_, SIGKILL);
        int status = 0;
        ::waitpid(pid_, &status, 0);
    }
    std::filesystem::remove(out_path_);
    std::filesystem::remove(err_path_);
}

void TvidProcess::send(int signal) const {
    if (pid_ > 0 && !exited_) ::kill(pid_, signal);
}

bool TvidProcess::wait(double seconds) {
    if (exited_) return true;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
        int status = 0;
        const pid_t done = ::waitpid(pid_, &status, WNOHANG);
        if (done == pid_) {
            exited_ = true;
            result_.exit_code = status_to_exit_code(status);
            result_.out = slurp(out_path_);
            result_.err = slurp(err_path_);
            return true;
        }
        if (std::chrono::steady_clock::now() >= deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

RunResult run_tvid_on_terminal(const std::vector<std::string>& args, TerminalStreams streams) {
    const std::string out_path = scratch_base() + ".out";
    struct winsize size {};
    size.ws_row = 40;
    size.ws_col = 160;
    int master = -1;
    const pid_t pid = ::forkpty(&master, nullptr, nullptr, &size);
    if (pid == 0) {
        if (streams == TerminalStreams::stderr_only) {
            const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            ::dup2(out, 1);
        }
        exec_tvid(args);
    }
    RunResult r;
    std::string terminal;
    char buf[4096];
    for (;;) {  // until the child closes the terminal (EIO once the slave side is gone)
        const ssize_t n = ::read(master, buf, sizeof buf);
        if (n > 0) terminal.append(buf, static_cast<std::size_t>(n));
        else if (n < 0 && errno == EINTR) continue;
        else break;
    }
    ::close(master);
    int status = 0;
    ::waitpid(pid, &status, 0);
    r.exit_code = status_to_exit_code(status);
    if (streams == TerminalStreams::stderr_only) {
        r.out = slurp(out_path);
        r.err = terminal;
        std::filesystem::remove(out_path);
    } else {
        r.out = terminal;
    }
    return r;
}

}  // namespace tvid::test
