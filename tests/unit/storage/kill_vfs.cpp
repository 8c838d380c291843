// SPDX-License-Identifier: Apache-2.0
#include "kill_vfs.hpp"

#include <signal.h>
#include <sqlite3.h>

#include <cstddef>
#include <cstdlib>

namespace ncqual::storage::testing {
namespace {

sqlite3_vfs* g_real = nullptr;  // the default VFS ("unix") everything is forwarded to
sqlite3_vfs g_shim;
sqlite3_io_methods g_methods;
KillTarget g_target = KillTarget::Wal;
long g_operations_left = 0;

// Our file: the shim's header, then the real VFS's file object in the same allocation.
struct ShimFile {
  sqlite3_file base;
  sqlite3_file* real;
  bool counted;  // a file of the kind we kill on
};

constexpr std::size_t kRealOffset = (sizeof(ShimFile) + 7) & ~std::size_t{7};

sqlite3_file* real_of(sqlite3_file* file) { return reinterpret_cast<ShimFile*>(file)->real; }

// Called before each modifying operation on a counted file.
void count(sqlite3_file* file) {
  if (!reinterpret_cast<ShimFile*>(file)->counted) return;
  if (--g_operations_left == 0) raise(SIGKILL);
}

int shim_close(sqlite3_file* f) { return real_of(f)->pMethods->xClose(real_of(f)); }
int shim_read(sqlite3_file* f, void* buffer, int amount, sqlite3_int64 offset) {
  return real_of(f)->pMethods->xRead(real_of(f), buffer, amount, offset);
}
int shim_write(sqlite3_file* f, const void* buffer, int amount, sqlite3_int64 offset) {
  count(f);
  return real_of(f)->pMethods->xWrite(real_of(f), buffer, amount, offset);
}
int shim_truncate(sqlite3_file* f, sqlite3_int64 size) {
  count(f);
  return real_of(f)->pMethods->xTruncate(real_of(f), size);
}
int shim_sync(sqlite3_file* f, int flags) {
  count(f);
  return real_of(f)->pMethods->xSync(real_of(f), flags);
}
int shim_file_size(sqlite3_file* f, sqlite3_int64* size) {
  return real_of(f)->pMethods->xFileSize(real_of(f), size);
}
int shim_lock(sqlite3_file* f, int level) { return real_of(f)->pMethods->xLock(real_of(f), level); }
int shim_unlock(sqlite3_file* f, int level) {
  return real_of(f)->pMethods->xUnlock(real_of(f), level);
}
int shim_check_reserved_lock(sqlite3_file* f, int* out) {
  return real_of(f)->pMethods->xCheckReservedLock(real_of(f), out);
}
int shim_file_control(sqlite3_file* f, int op, void* arg) {
  return real_of(f)->pMethods->xFileControl(real_of(f), op, arg);
}
int shim_sector_size(sqlite3_file* f) { return real_of(f)->pMethods->xSectorSize(real_of(f)); }
int shim_device_characteristics(sqlite3_file* f) {
  return real_of(f)->pMethods->xDeviceCharacteristics(real_of(f));
}
int shim_shm_map(sqlite3_file* f, int region, int size, int extend, void volatile** out) {
  return real_of(f)->pMethods->xShmMap(real_of(f), region, size, extend, out);
}
int shim_shm_lock(sqlite3_file* f, int offset, int n, int flags) {
  return real_of(f)->pMethods->xShmLock(real_of(f), offset, n, flags);
}
void shim_shm_barrier(sqlite3_file* f) { real_of(f)->pMethods->xShmBarrier(real_of(f)); }
int shim_shm_unmap(sqlite3_file* f, int delete_flag) {
  return real_of(f)->pMethods->xShmUnmap(real_of(f), delete_flag);
}
int shim_fetch(sqlite3_file* f, sqlite3_int64 offset, int amount, void** out) {
  return real_of(f)->pMethods->xFetch(real_of(f), offset, amount, out);
}
int shim_unfetch(sqlite3_file* f, sqlite3_int64 offset, void* page) {
  return real_of(f)->pMethods->xUnfetch(real_of(f), offset, page);
}

int shim_open(sqlite3_vfs*, sqlite3_filename name, sqlite3_file* file, int flags, int* out_flags) {
  auto* shim = reinterpret_cast<ShimFile*>(file);
  shim->base.pMethods = nullptr;  // until the real open succeeds: SQLite then skips xClose
  shim->real = reinterpret_cast<sqlite3_file*>(reinterpret_cast<char*>(file) + kRealOffset);
  const int wanted = g_target == KillTarget::Wal ? SQLITE_OPEN_WAL : SQLITE_OPEN_MAIN_DB;
  shim->counted = (flags & wanted) != 0;
  const int rc = g_real->xOpen(g_real, name, shim->real, flags, out_flags);
  if (shim->real->pMethods != nullptr) shim->base.pMethods = &g_methods;
  return rc;
}

}  // namespace

void install_kill_vfs(KillTarget target, long n) {
  g_real = sqlite3_vfs_find(nullptr);
  if (g_real == nullptr || g_real->iVersion < 3) std::abort();
  g_target = target;
  g_operations_left = n;

  g_methods = sqlite3_io_methods{};
  g_methods.iVersion = 3;  // the unix VFS's files are version 3 (WAL shared memory, mmap)
  g_methods.xClose = shim_close;
  g_methods.xRead = shim_read;
  g_methods.xWrite = shim_write;
  g_methods.xTruncate = shim_truncate;
  g_methods.xSync = shim_sync;
  g_methods.xFileSize = shim_file_size;
  g_methods.xLock = shim_lock;
  g_methods.xUnlock = shim_unlock;
  g_methods.xCheckReservedLock = shim_check_reserved_lock;
  g_methods.xFileControl = shim_file_control;
  g_methods.xSectorSize = shim_sector_size;
  g_methods.xDeviceCharacteristics = shim_device_characteristics;
  g_methods.xShmMap = shim_shm_map;
  g_methods.xShmLock = shim_shm_lock;
  g_methods.xShmBarrier = shim_shm_barrier;
  g_methods.xShmUnmap = shim_shm_unmap;
  g_methods.xFetch = shim_fetch;
  g_methods.xUnfetch = shim_unfetch;

  // Everything but opening goes straight to the real VFS's functions; they get our struct, a
  // copy of the real one (same pAppData and limits).
  g_shim = *g_real;
  g_shim.zName = "ncqual_kill";
  g_shim.pNext = nullptr;
  g_shim.szOsFile = static_cast<int>(kRealOffset) + g_real->szOsFile;
  g_shim.xOpen = shim_open;
  if (sqlite3_vfs_register(&g_shim, 1) != SQLITE_OK) std::abort();
}

}  // namespace ncqual::storage::testing
