// SPDX-License-Identifier: Apache-2.0
// A shim SQLite VFS for crash tests: forwards everything to the default VFS and SIGKILLs the
// process just before the n-th write, sync or truncate of a chosen kind of file. Lets a test die
// at an exact point inside a transaction (or a checkpoint) instead of wherever a signal from
// outside happens to land.
//
// Install only in a forked child: it becomes the default VFS of the whole process.
#pragma once

namespace ncqual::storage::testing {

enum class KillTarget {
  Wal,           // the -wal file: where every commit goes
  MainDatabase,  // the database file itself: written only by checkpoints in WAL mode
};

// Registers the shim as the default VFS; the process kills itself before the `n`-th (1-based)
// write, sync or truncate of a `target` file.
void install_kill_vfs(KillTarget target, long n);

}  // namespace ncqual::storage::testing
