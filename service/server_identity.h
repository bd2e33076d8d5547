// Who a server is, for the job store's owners and leases (job_store.h): an instance id, random per
// process start, and a home that the server's restarts share, kept in the data folder.
//
// Homes are slots, one file each in <data>/servers/ named after the host (<host>.<n>), holding a
// random id written when the slot was made. A server takes the first slot of its host that no
// live process holds (an exclusive flock, kept for the process's life and released by the kernel
// however the process ends), making one when all are held. So two servers running at once on one
// host and data folder never share a home, and a server restarted after a crash (or a clean stop)
// takes the slot its predecessor left, and with it the jobs that predecessor ran: its local workers
// died with it, so they can go back to the queue at once instead of waiting for their leases.
#pragma once
#include <string>

#include "service/job_store.h"

namespace lorgnette::service {

class ServerIdentity {
 public:
  // Throws with the path when the slot folder cannot be made or written.
  explicit ServerIdentity(const std::string& data_dir);
  ~ServerIdentity();
  ServerIdentity(const ServerIdentity&) = delete;
  ServerIdentity& operator=(const ServerIdentity&) = delete;

  const JobOwner& owner() const { return owner_; }
  const std::string& slot_path() const { return slot_; }

 private:
  int fd_ = -1;
  std::string slot_;
  JobOwner owner_;
};

// This machine's host name ("localhost" when it has none).
std::string host_name();

// An owner with a fresh home of its own (nothing persisted): for an executor used without a data
// folder identity, e.g. by a test, which then adopts only expired leases.
JobOwner ephemeral_owner();

}  // namespace lorgnette::service
