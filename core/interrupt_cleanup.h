#pragma once
// Ctrl-C (SIGINT) and SIGTERM end a command within moments, and take its
// temporary files with them: every AtomicOutput registers its temporary here
// while it is being written, and the handler unlinks what is registered,
// prints what it did and exits 130 (SIGINT) or 143 (SIGTERM). The handler uses
// only async-signal-safe calls (unlink, write, _exit), so it works whatever the
// interrupted thread was doing (inside HDF5, OpenImageIO or TBB).
#include <string>

namespace acpca::interrupt {

/// Installs the SIGINT and SIGTERM handlers, also where the parent started the
/// process with the signal ignored (a script's background job); SIGXFSZ is
/// ignored, so that a write past ulimit -f fails as an error.
void installHandlers();

/// Registers a temporary file the handler removes; returns its slot (-1 when
/// every slot is taken: the file is then only removed by the next run).
int registerTemporary(const std::string& path);

/// The temporary of `slot` is gone or in place: the handler leaves it alone.
void releaseTemporary(int slot);

/// A line the handler prints after removing the temporaries (for example where
/// finished work was kept); empty clears it.
void setInterruptNote(const std::string& note);

/// How many temporaries are registered now (for tests).
int registeredTemporaries();

}  // namespace acpca::interrupt
