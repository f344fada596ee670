#pragma once
// The ranks of an MPI job (`mpirun -np K adaptive-cpca ...`). A process that
// mpirun did not start, or a build without MPI (ACPCA_MPI off), is rank 0 of
// 1, and every function here is then a no-op or an identity: callers need no
// #ifdef. Only one thread at a time may call these (MPI_THREAD_SERIALIZED).
// Receives and collectives wait by polling with short sleeps, not by spinning
// as MPI does: a waiting rank leaves its core to the ranks that compute.
#include <string>
#include <vector>

namespace acpca::ranks {

/// Lives in main(): starts MPI when mpirun started the process (its
/// environment says so) and ends it on the way out.
class Session {
 public:
  Session(int& argc, char**& argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

int rank();
int count();
inline bool distributed() {
  return count() > 1;
}
/// Whether this build can run distributed at all.
bool built();

/// Sends floats to rank `to` under `tag` (0 <= tag < 32767; 32767 is the
/// receiver's ready token). Blocks until the receiver takes them, so the
/// receiver's pace bounds the memory in flight; waits sleeping, not polling.
void send(int to, int tag, const std::vector<float>& values);
/// Receives what `send` sent from rank `from` under `tag`, whatever its length.
std::vector<float> receive(int from, int tag);

/// The same for bytes (a serialized message, a file's contents).
void sendBytes(int to, int tag, const std::vector<char>& bytes);
std::vector<char> receiveBytes(int from, int tag);
/// Receives what sendBytes sent under `tag` from whichever rank sent first;
/// `from` says which.
std::vector<char> receiveBytesFromAny(int tag, int& from);
/// Whether a message under `tag` is waiting (from any rank).
bool pending(int tag);
/// What a rank waiting on others does between polls: sleep briefly (0.5 ms),
/// leaving its core to the ranks that compute.
void sleepBetweenPolls();
/// Rank 0's bytes, on every rank (a no-op when not distributed).
void broadcast(std::vector<char>& bytes);

/// The sum over every rank (integers: exact, whatever the order).
long long sum(long long value);

/// Ends every rank of the job with this exit code (a rank that failed while
/// others wait on it must not wait in MPI_Finalize); returns the code as is
/// when not distributed.
int abortAll(int code);

/// "rank 2 of 3: " under mpirun, "" otherwise: for messages that name a rank.
std::string prefix();

}  // namespace acpca::ranks
