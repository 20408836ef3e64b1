#pragma once
// The processes of one run: under `mpirun -n K` (a build with TVID_WITH_MPI) the K MPI
// ranks, otherwise this process alone. Rank 0, the root, reads the command line's files,
// writes every report and prints; the others score candidates or run batch jobs for it.
//
// Every wait (a collective, a receive) polls the MPI library and sleeps in between, so a
// process waiting for the root does not keep a core busy. All calls may come from any
// thread; they are serialized inside.

#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

namespace tvid {

class ProcessGroup {
public:
    /// This process alone (no MPI).
    ProcessGroup();
    /// In a build with MPI and when started by an MPI launcher (mpirun, mpiexec, srun): the
    /// launcher's processes (MPI is initialized here and finalized by the destructor).
    /// Otherwise this process alone, without initializing MPI.
    ProcessGroup(int& argc, char**& argv);
    ~ProcessGroup();
    ProcessGroup(const ProcessGroup&) = delete;
    ProcessGroup& operator=(const ProcessGroup&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    bool is_root() const { return rank_ == 0; }

    /// Collective: every process ends up with the root's `bytes` / `values`.
    void broadcast(std::string& bytes);
    void broadcast(std::vector<double>& values);

    /// Collective: on the root, every process's `mine` in rank order (values concatenated);
    /// empty on the others.
    std::vector<std::string> gather(const std::string& mine);
    std::vector<double> gather(const std::vector<double>& mine);

    /// Point to point. `any` matches every source or tag in receive().
    static constexpr int any = -1;
    struct Message {
        int source = 0;
        int tag = 0;
        std::string bytes;
    };
    /// Returns once `bytes` is on its way (it may not have been received yet).
    void send(int destination, int tag, const std::string& bytes);
    /// Waits for the next message from `source` with `tag`.
    Message receive(int source, int tag);

private:
    int rank_ = 0;
    int size_ = 1;
    bool mpi_ = false;   ///< MPI was initialized by this object
    std::mutex calls_;   ///< one MPI call at a time (MPI_THREAD_SERIALIZED)
};

/// The slice [begin, end) of `count` items that process `rank` of `size` takes: contiguous,
/// in rank order, sizes differing by at most one.
struct ProcessSlice {
    std::size_t begin = 0, end = 0;
    std::size_t size() const { return end - begin; }
};
ProcessSlice process_slice(std::size_t count, int rank, int size);

}  // namespace tvid
