// Open MPI behind MpiLink.
#include "cluster/mpi_link.h"

#include <mpi.h>
#include <sched.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

namespace frameless::cluster {

int launched_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_SIZE"})
    if (const char* v = std::getenv(name); v && *v) return std::max(1, std::atoi(v));
  return 1;
}

MpiLink::MpiLink() {
  int provided = 0;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
    throw std::runtime_error("cluster: MPI_Init_thread failed");
  if (provided < MPI_THREAD_SERIALIZED) {
    MPI_Finalize();
    throw std::runtime_error("cluster: this MPI cannot serve a communication thread (MPI_THREAD_SERIALIZED)");
  }
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
  // mpirun binds each rank to one core by default (-np 2 and up to the core count): a rank runs
  // a multithreaded render loop, so it takes back every core of its node before any thread
  // starts (threads inherit this mask). Where the system forbids it, the binding stays.
  cpu_set_t all;
  CPU_ZERO(&all);
  const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  for (long c = 0; c < cpus && c < CPU_SETSIZE; ++c) CPU_SET(int(c), &all);
  sched_setaffinity(0, sizeof all, &all);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

struct MpiLink::Pending {
  MPI_Request request = MPI_REQUEST_NULL;
  std::vector<uint8_t> bytes;
};

MpiLink::~MpiLink() {
  flush();
  MPI_Finalize();
}

void MpiLink::send_async(int dest, int tag, std::vector<uint8_t> bytes) {
  auto p = std::make_unique<Pending>();
  p->bytes = std::move(bytes);
  MPI_Isend(p->bytes.data(), int(p->bytes.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD, &p->request);
  pending_.push_back(std::move(p));
  progress();
}

void MpiLink::progress() {
  for (size_t i = 0; i < pending_.size();) {
    int done = 0;
    MPI_Test(&pending_[i]->request, &done, MPI_STATUS_IGNORE);
    if (done) {
      pending_[i] = std::move(pending_.back());
      pending_.pop_back();
    } else {
      ++i;
    }
  }
}

void MpiLink::flush() {
  for (auto& p : pending_) MPI_Wait(&p->request, MPI_STATUS_IGNORE);
  pending_.clear();
}

void MpiLink::send(int dest, int tag, const std::vector<uint8_t>& bytes) {
  MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD);
}

bool MpiLink::poll(int source, int tag, std::vector<uint8_t>& bytes, int* from) {
  if (!pending_.empty()) progress();
  int flag = 0;
  MPI_Status st;
  MPI_Iprobe(source < 0 ? MPI_ANY_SOURCE : source, tag, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return false;
  int count = 0;
  MPI_Get_count(&st, MPI_BYTE, &count);
  if (count < 0 || count > kMaxMessageBytes)
    throw std::runtime_error("cluster: rank " + std::to_string(st.MPI_SOURCE) + " sent a message of " +
                             std::to_string(count) + " bytes (limit " + std::to_string(kMaxMessageBytes) + ")");
  bytes.resize(size_t(count));
  MPI_Recv(bytes.data(), count, MPI_BYTE, st.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  if (from) *from = st.MPI_SOURCE;
  return true;
}

std::vector<std::vector<uint8_t>> MpiLink::gather(const std::vector<uint8_t>& mine) {
  int n = int(mine.size());
  std::vector<int> sizes(rank_ == 0 ? size_t(size_) : 0);
  MPI_Gather(&n, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets(sizes.size(), 0);
  int total = 0;
  for (size_t r = 0; r < sizes.size(); ++r) {
    offsets[r] = total;
    total += sizes[r];
  }
  std::vector<uint8_t> all(static_cast<size_t>(total));
  MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE, 0,
              MPI_COMM_WORLD);
  std::vector<std::vector<uint8_t>> out(sizes.size());
  for (size_t r = 0; r < sizes.size(); ++r)
    out[r].assign(all.begin() + offsets[r], all.begin() + offsets[r] + sizes[r]);
  return out;
}

void MpiLink::broadcast(std::vector<uint8_t>& bytes) {
  int n = int(bytes.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
  bytes.resize(size_t(n));
  MPI_Bcast(bytes.data(), n, MPI_BYTE, 0, MPI_COMM_WORLD);
}

void MpiLink::abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace frameless::cluster
