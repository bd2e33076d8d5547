// Renews the leases of the jobs this server runs (job_store.h, LeaseSettings in executor.h) from a
// thread of its own, every sixth of the lease: the server's liveness, independent of its executor's
// loop, which may wait up to half a minute on a slow Slurm controller.
#pragma once
#include <condition_variable>
#include <mutex>
#include <thread>

#include "service/executor.h"
#include "service/job_store.h"

namespace lorgnette::service {

class LeaseKeeper {
 public:
  LeaseKeeper(JobStore& store, LeaseSettings lease);
  ~LeaseKeeper();  // stops renewing (the leases then run out unless the next start adopts them)
  LeaseKeeper(const LeaseKeeper&) = delete;
  LeaseKeeper& operator=(const LeaseKeeper&) = delete;

 private:
  void run();

  JobStore& store_;
  LeaseSettings lease_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace lorgnette::service
