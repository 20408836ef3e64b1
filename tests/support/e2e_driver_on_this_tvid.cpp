// Runs an end-to-end test driver built in another tree (TVID_E2E_DRIVER: the release tree's
// tests/tvid_e2e_tests) on this tree's tvid binary. The sanitizer tree uses it: what the
// end-to-end tests check is the tool they run, so the sanitizers belong on the tool, and
// the driver (Catch2 assertions, reading JSON) is compiled once, in the release tree.
//
// Sets TVID_BINARY to this tree's tvid and TVID_TEST_TIME_SCALE, then replaces itself with
// the driver, passing every argument on (test names, Catch2 options).

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <unistd.h>

int main(int argc, char** argv) {
    ::setenv("TVID_BINARY", TVID_BINARY, 1);
    ::setenv("TVID_TEST_TIME_SCALE", TVID_TEST_TIME_SCALE_TEXT, 1);
    argv[0] = const_cast<char*>(TVID_E2E_DRIVER);
    (void)argc;
    ::execv(TVID_E2E_DRIVER, argv);
    std::fprintf(stderr, "e2e driver: cannot run %s: %s\n", TVID_E2E_DRIVER, std::strerror(errno));
    return 127;
}
