// The process group of a build without MPI: this process alone.

#include <stdexcept>

#include "tvid/parallel/process_group.hpp"

namespace tvid {

ProcessGroup::ProcessGroup() = default;
ProcessGroup::ProcessGroup(int&, char**&) {}
ProcessGroup::~ProcessGroup() = default;

void ProcessGroup::broadcast(std::string&) {}
void ProcessGroup::broadcast(std::vector<double>&) {}
std::vector<std::string> ProcessGroup::gather(const std::string& mine) { return {mine}; }
std::vector<double> ProcessGroup::gather(const std::vector<double>& mine) { return mine; }

void ProcessGroup::send(int, int, const std::string&) {
    throw std::logic_error("process group: no other process to send to");
}
ProcessGroup::Message ProcessGroup::receive(int, int) {
    throw std::logic_error("process group: no other process to receive from");
}

}  // namespace tvid
