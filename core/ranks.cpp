#include "core/ranks.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <thread>

#include "core/error.h"

#ifdef ACPCA_WITH_MPI
#include <mpi.h>
#endif

namespace acpca::ranks {

namespace {

int thisRank = 0, rankCount = 1;

#ifdef ACPCA_WITH_MPI
bool started = false;

/// mpirun (Open MPI, or a PMI/PMIx launcher) leaves these in each rank's
/// environment; a plain start has none, and skips MPI_Init's start-up cost.
bool launchedByMpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

constexpr long long kChunk = 1ll << 28;  // floats per message: counts are ints

/// Open MPI waits by polling, a whole core per waiting rank: with a rank per
/// core, a rank waiting on a slower one took 40% of the cycles of a 2x1 build
/// (a sibling hyperthread's, or oversubscribed ranks'). Waits that can be long
/// poll with a short sleep between tries instead; the transfer that follows
/// finds both sides in MPI.
template <typename Ready>
void waitSleeping(Ready&& ready) {
  while (!ready()) sleepBetweenPolls();
}

/// The source of the first message under `tag` from `from` (or any rank).
int probeSleeping(int from, int tag) {
  MPI_Status status;
  int flag = 0;
  waitSleeping([&] {
    MPI_Iprobe(from, tag, MPI_COMM_WORLD, &flag, &status);
    return flag != 0;
  });
  return status.MPI_SOURCE;
}

/// Every rank has arrived: the collective that follows does not wait long.
void barrierSleeping() {
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  int done = 0;
  waitSleeping([&] {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    return done != 0;
  });
}
#endif

}  // namespace

Session::Session(int& argc, char**& argv) {
#ifdef ACPCA_WITH_MPI
  if (!launchedByMpirun()) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
  started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &thisRank);
  MPI_Comm_size(MPI_COMM_WORLD, &rankCount);
#else
  (void)argc;
  (void)argv;
#endif
}

Session::~Session() {
#ifdef ACPCA_WITH_MPI
  if (started) MPI_Finalize();
#endif
}

int rank() {
  return thisRank;
}

int count() {
  return rankCount;
}

bool built() {
#ifdef ACPCA_WITH_MPI
  return true;
#else
  return false;
#endif
}

#ifdef ACPCA_WITH_MPI
namespace {

/// The receiver's "ready for your values" token. Message tags of the callers
/// stay below it (MPI guarantees tags up to 32767).
constexpr int kReadyTag = 32767;

/// A length (small: it goes at once), then, once the receiver says it is
/// ready, the values in chunks MPI's int counts can hold. A large blocking
/// send waits for the receiver by polling, a whole core for as long as the
/// receiver computes (rank 0 between its own bands or frames); the sender
/// waits for the token sleeping instead, and the transfer then finds both
/// sides in MPI.
template <typename T>
void sendValues(int to, int tag, const std::vector<T>& values, MPI_Datatype type) {
  long long size = static_cast<long long>(values.size());
  MPI_Send(&size, 1, MPI_LONG_LONG, to, tag, MPI_COMM_WORLD);
  if (size == 0) return;
  probeSleeping(to, kReadyTag);
  char token = 0;
  MPI_Recv(&token, 1, MPI_CHAR, to, kReadyTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  for (long long first = 0; first < size; first += kChunk)
    MPI_Send(values.data() + first, static_cast<int>(std::min(kChunk, size - first)), type, to, tag,
             MPI_COMM_WORLD);
}

template <typename T>
std::vector<T> receiveValues(int from, int tag, MPI_Datatype type) {
  ACPCA_CHECK(tag >= 0 && tag < kReadyTag, "message tag ", tag, " is reserved or out of range");
  from = probeSleeping(from, tag);
  long long size = 0;
  MPI_Recv(&size, 1, MPI_LONG_LONG, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::vector<T> values(static_cast<size_t>(size));
  if (size == 0) return values;
  const char token = 1;
  MPI_Send(&token, 1, MPI_CHAR, from, kReadyTag, MPI_COMM_WORLD);
  for (long long first = 0; first < size; first += kChunk)
    MPI_Recv(values.data() + first, static_cast<int>(std::min(kChunk, size - first)), type, from,
             tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return values;
}

}  // namespace
#endif

void send(int to, int tag, const std::vector<float>& values) {
#ifdef ACPCA_WITH_MPI
  sendValues(to, tag, values, MPI_FLOAT);
#else
  (void)to, (void)tag, (void)values;
  ACPCA_CHECK(false, "send without MPI");
#endif
}

std::vector<float> receive(int from, int tag) {
#ifdef ACPCA_WITH_MPI
  return receiveValues<float>(from, tag, MPI_FLOAT);
#else
  (void)from, (void)tag;
  ACPCA_CHECK(false, "receive without MPI");
  return {};
#endif
}

void sendBytes(int to, int tag, const std::vector<char>& bytes) {
#ifdef ACPCA_WITH_MPI
  sendValues(to, tag, bytes, MPI_BYTE);
#else
  (void)to, (void)tag, (void)bytes;
  ACPCA_CHECK(false, "send without MPI");
#endif
}

std::vector<char> receiveBytes(int from, int tag) {
#ifdef ACPCA_WITH_MPI
  return receiveValues<char>(from, tag, MPI_BYTE);
#else
  (void)from, (void)tag;
  ACPCA_CHECK(false, "receive without MPI");
  return {};
#endif
}

std::vector<char> receiveBytesFromAny(int tag, int& from) {
#ifdef ACPCA_WITH_MPI
  from = probeSleeping(MPI_ANY_SOURCE, tag);  // then its messages under the tag arrive in order
  return receiveValues<char>(from, tag, MPI_BYTE);
#else
  (void)tag, (void)from;
  ACPCA_CHECK(false, "receive without MPI");
  return {};
#endif
}

bool pending(int tag) {
#ifdef ACPCA_WITH_MPI
  int flag = 0;
  MPI_Iprobe(MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
  return flag != 0;
#else
  (void)tag;
  return false;
#endif
}

void sleepBetweenPolls() {
  std::this_thread::sleep_for(std::chrono::microseconds(500));
}

void broadcast(std::vector<char>& bytes) {
#ifdef ACPCA_WITH_MPI
  if (rankCount <= 1) return;
  barrierSleeping();  // rank 0 may still be computing what it sends
  long long size = static_cast<long long>(bytes.size());
  MPI_Bcast(&size, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  bytes.resize(static_cast<size_t>(size));
  for (long long first = 0; first < size; first += kChunk)
    MPI_Bcast(bytes.data() + first, static_cast<int>(std::min(kChunk, size - first)), MPI_BYTE, 0,
              MPI_COMM_WORLD);
#else
  (void)bytes;
#endif
}

long long sum(long long value) {
#ifdef ACPCA_WITH_MPI
  if (rankCount > 1) {
    long long total = 0;
    barrierSleeping();
    MPI_Allreduce(&value, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    return total;
  }
#endif
  return value;
}

int abortAll(int code) {
#ifdef ACPCA_WITH_MPI
  if (rankCount > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  return code;
}

std::string prefix() {
  return rankCount > 1 ? concat("rank ", thisRank, " of ", rankCount, ": ") : std::string();
}

}  // namespace acpca::ranks
