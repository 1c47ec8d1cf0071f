// What a program leaves behind when SIGINT, SIGTERM or SIGHUP stops it: nothing. Temporary
// outputs (a PNG being written beside its name), a reader worker's private folder and the worker
// itself are registered here while they exist; a program that calls installCleanupOnSignals
// (the wirefur command does; a host such as ParaView keeps its own handlers) then removes them
// and kills the worker before it dies of the signal, as it would have without the handler.
//
// The handler is async-signal-safe: the paths live in fixed slots written before they are
// published, the folder is emptied with open / getdents64 / unlinkat, and nothing allocates.
#pragma once

#include <string>
#include <sys/types.h>

namespace wf {

/// Registers a file (folder = false) or a folder and the files in it (folder = true) to remove
/// on a fatal signal. Returns a slot for forgetCleanup, or -1 when all 256 slots are taken or
/// the path is too long (it is then simply not cleaned up on a signal).
int registerCleanup(const std::string& path, bool folder);
void forgetCleanup(int slot);

/// A worker now running (runWorker registers each, up to 64 at once): killed and reaped by the
/// handler before the folders go. Returns a slot for forgetCleanupChild, or -1.
int registerCleanupChild(pid_t pid);
void forgetCleanupChild(int slot);

/// Installs the handler for SIGINT, SIGTERM and SIGHUP (once; later calls do nothing).
void installCleanupOnSignals();

}  // namespace wf
