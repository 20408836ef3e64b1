// The process group of a build with MPI (TVID_WITH_MPI): MPI_COMM_WORLD of the launcher's
// processes, through the MPI C API. Every operation is non-blocking underneath and waited
// for by polling (wait_for), so a waiting process sleeps instead of spinning a core.

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#include "tvid/parallel/process_group.hpp"

namespace tvid {

namespace {

// Set by the launchers of Open MPI, PMIx (srun, prterun) and MPICH's Hydra.
bool started_by_mpi_launcher() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(name)) return true;
    return false;
}

void check(int status, const char* what) {
    if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

int int_count(std::size_t n) {
    if (n > static_cast<std::size_t>(INT32_MAX)) throw std::length_error("MPI: message too long");
    return static_cast<int>(n);
}

// Tests `request` until it completes, sleeping between tests: 10 µs at first, doubling
// up to 1 ms, so a long wait costs about a thousand short wake-ups a second.
void wait_for(MPI_Request& request, std::mutex& calls) {
    auto pause = std::chrono::microseconds(10);
    for (;;) {
        int done = 0;
        {
            const std::lock_guard<std::mutex> lock(calls);
            check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), "MPI_Test");
        }
        if (done) return;
        std::this_thread::sleep_for(pause);
        pause = std::min(pause * 2, std::chrono::microseconds(1000));
    }
}

// Rank 0's container (a string or a vector) to every process: its length, then its
// elements of MPI type `type`.
template <class Container>
void broadcast_container(Container& values, MPI_Datatype type, std::mutex& calls) {
    std::uint64_t length = values.size();
    MPI_Request request;
    {
        const std::lock_guard<std::mutex> lock(calls);
        check(MPI_Ibcast(&length, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &request), "MPI_Ibcast");
    }
    wait_for(request, calls);
    values.resize(length);
    if (length == 0) return;
    {
        const std::lock_guard<std::mutex> lock(calls);
        check(MPI_Ibcast(values.data(), int_count(length), type, 0, MPI_COMM_WORLD, &request), "MPI_Ibcast");
    }
    wait_for(request, calls);
}

}  // namespace

ProcessGroup::ProcessGroup() = default;

ProcessGroup::ProcessGroup(int& argc, char**& argv) {
    if (!started_by_mpi_launcher()) return;
    int provided = MPI_THREAD_SINGLE;
    check(MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided), "MPI_Init_thread");
    mpi_ = true;
    if (provided < MPI_THREAD_SERIALIZED)
        throw std::runtime_error("MPI: the library does not allow calls from several threads (MPI_THREAD_SERIALIZED)");
    check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
}

ProcessGroup::~ProcessGroup() {
    if (mpi_) MPI_Finalize();
}

void ProcessGroup::broadcast(std::string& bytes) {
    if (size_ > 1) broadcast_container(bytes, MPI_CHAR, calls_);
}

void ProcessGroup::broadcast(std::vector<double>& values) {
    if (size_ > 1) broadcast_container(values, MPI_DOUBLE, calls_);
}

namespace {

// MPI_Igatherv of `count` items at `mine` to the root: first every count, then the items.
// Returns the counts on the root (empty elsewhere); `all` receives the items there.
template <class T>
std::vector<int> gather_items(const T* mine, int count, MPI_Datatype type, std::vector<T>& all, int rank, int size,
                              std::mutex& calls) {
    std::vector<int> counts(rank == 0 ? static_cast<std::size_t>(size) : 0);
    MPI_Request request;
    {
        const std::lock_guard<std::mutex> lock(calls);
        check(MPI_Igather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD, &request), "MPI_Igather");
    }
    wait_for(request, calls);
    std::vector<int> offsets(counts.size(), 0);
    std::size_t total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
        offsets[r] = int_count(total);
        total += static_cast<std::size_t>(counts[r]);
    }
    all.resize(total);
    {
        const std::lock_guard<std::mutex> lock(calls);
        check(MPI_Igatherv(mine, count, type, all.data(), counts.data(), offsets.data(), type, 0, MPI_COMM_WORLD,
                           &request),
              "MPI_Igatherv");
    }
    wait_for(request, calls);
    return counts;
}

}  // namespace

std::vector<std::string> ProcessGroup::gather(const std::string& mine) {
    if (size_ == 1) return {mine};
    std::vector<char> all;
    const std::vector<int> counts =
        gather_items(mine.data(), int_count(mine.size()), MPI_CHAR, all, rank_, size_, calls_);
    std::vector<std::string> out;
    std::size_t at = 0;
    for (int n : counts) {
        out.emplace_back(all.data() + at, static_cast<std::size_t>(n));
        at += static_cast<std::size_t>(n);
    }
    return out;
}

std::vector<double> ProcessGroup::gather(const std::vector<double>& mine) {
    if (size_ == 1) return mine;
    std::vector<double> all;
    gather_items(mine.data(), int_count(mine.size()), MPI_DOUBLE, all, rank_, size_, calls_);
    return all;
}

void ProcessGroup::send(int destination, int tag, const std::string& bytes) {
    if (size_ == 1) throw std::logic_error("process group: no other process to send to");
    MPI_Request request;
    {
        const std::lock_guard<std::mutex> lock(calls_);
        check(MPI_Isend(bytes.data(), int_count(bytes.size()), MPI_CHAR, destination, tag, MPI_COMM_WORLD, &request),
              "MPI_Isend");
    }
    wait_for(request, calls_);
}

ProcessGroup::Message ProcessGroup::receive(int source, int tag) {
    if (size_ == 1) throw std::logic_error("process group: no other process to receive from");
    auto pause = std::chrono::microseconds(10);
    for (;;) {
        {
            const std::lock_guard<std::mutex> lock(calls_);
            int found = 0;
            MPI_Message handle;
            MPI_Status status;
            check(MPI_Improbe(source == any ? MPI_ANY_SOURCE : source, tag == any ? MPI_ANY_TAG : tag, MPI_COMM_WORLD,
                              &found, &handle, &status),
                  "MPI_Improbe");
            if (found) {
                int length = 0;
                check(MPI_Get_count(&status, MPI_CHAR, &length), "MPI_Get_count");
                Message m{status.MPI_SOURCE, status.MPI_TAG, std::string(static_cast<std::size_t>(length), '\0')};
                // Matched, so no other receive can take it; its data is on its way.
                check(MPI_Mrecv(m.bytes.data(), length, MPI_CHAR, &handle, MPI_STATUS_IGNORE), "MPI_Mrecv");
                return m;
            }
        }
        std::this_thread::sleep_for(pause);
        pause = std::min(pause * 2, std::chrono::microseconds(1000));
    }
}

}  // namespace tvid
