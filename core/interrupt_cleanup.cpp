#include "core/interrupt_cleanup.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>

namespace acpca::interrupt {

namespace {

// Fixed storage: the handler must not allocate or take locks. A slot is free
// (0), being filled or emptied (1) or live (2); the handler touches live ones.
constexpr int kSlots = 256;
constexpr size_t kPathBytes = 4096;
std::atomic<int> slotState[kSlots];
char slotPath[kSlots][kPathBytes];

constexpr size_t kNoteBytes = 1024;
std::atomic<int> noteState{0};  // 0 none, 1 being written, 2 set
char noteText[kNoteBytes];

void writeAll(const char* text, size_t length) {
  while (length > 0) {
    const ssize_t n = ::write(STDERR_FILENO, text, length);
    if (n <= 0) return;
    text += n, length -= static_cast<size_t>(n);
  }
}

void writeText(const char* text) {
  writeAll(text, std::strlen(text));
}

void writeNumber(long value) {
  char digits[24];
  int n = 0;
  do digits[n++] = static_cast<char>('0' + value % 10), value /= 10;
  while (value > 0 && n < 23);
  char out[24];
  for (int i = 0; i < n; ++i) out[i] = digits[n - 1 - i];
  writeAll(out, static_cast<size_t>(n));
}

std::atomic<int> handling{0};

void onSignal(int signal) {
  // A second signal while the first is handled waits for the first's _exit.
  if (handling.exchange(1) != 0) {
    for (;;) ::pause();
  }
  long removed = 0;
  for (int s = 0; s < kSlots; ++s)
    if (slotState[s].load() == 2 && ::unlink(slotPath[s]) == 0) ++removed;
  writeText("\nadaptive-cpca: ");
  writeText(signal == SIGINT ? "interrupted (SIGINT)" : "terminated (SIGTERM)");
  if (removed > 0) {
    writeText("; removed ");
    writeNumber(removed);
    writeText(removed == 1 ? " unfinished file" : " unfinished files");
  }
  writeText("\n");
  if (noteState.load() == 2) {
    writeText("adaptive-cpca: ");
    writeText(noteText);
    writeText("\n");
  }
  ::_exit(128 + signal);
}

}  // namespace

void installHandlers() {
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  action.sa_flags = SA_RESTART;
  // sigaction replaces SIG_IGN too: a background job (`cmd &` in a script
  // starts with SIGINT ignored) still stops and cleans up.
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
  // Past ulimit -f a write fails with EFBIG, which the writers report naming
  // the file (and their temporaries go), instead of SIGXFSZ ending the process.
  ::signal(SIGXFSZ, SIG_IGN);
  // Unblock them in this thread; threads started later inherit the mask.
  sigset_t both;
  sigemptyset(&both);
  sigaddset(&both, SIGINT);
  sigaddset(&both, SIGTERM);
  ::pthread_sigmask(SIG_UNBLOCK, &both, nullptr);
}

int registerTemporary(const std::string& path) {
  if (path.size() >= kPathBytes) return -1;
  for (int s = 0; s < kSlots; ++s) {
    int expected = 0;
    if (!slotState[s].compare_exchange_strong(expected, 1)) continue;
    std::memcpy(slotPath[s], path.c_str(), path.size() + 1);
    slotState[s].store(2);
    return s;
  }
  return -1;
}

void releaseTemporary(int slot) {
  if (slot >= 0 && slot < kSlots) slotState[slot].store(0);
}

void setInterruptNote(const std::string& note) {
  noteState.store(1);
  const size_t n = std::min(note.size(), kNoteBytes - 1);
  std::memcpy(noteText, note.data(), n);
  noteText[n] = '\0';
  noteState.store(note.empty() ? 0 : 2);
}

int registeredTemporaries() {
  int n = 0;
  for (int s = 0; s < kSlots; ++s) n += slotState[s].load() == 2;
  return n;
}

}  // namespace acpca::interrupt
