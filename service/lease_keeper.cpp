// The lease renewal thread (lease_keeper.h).
#include "service/lease_keeper.h"

#include <spdlog/spdlog.h>

namespace lorgnette::service {

LeaseKeeper::LeaseKeeper(JobStore& store, LeaseSettings lease)
    : store_(store), lease_(std::move(lease)), thread_([this] { run(); }) {}

LeaseKeeper::~LeaseKeeper() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void LeaseKeeper::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    lock.unlock();
    try {
      store_.renew_leases(lease_.owner.instance);
    } catch (const std::exception& e) {
      // A database that is down now: the next renewal tries again; the lease covers five misses.
      spdlog::warn("cannot renew this server's job leases: {}", e.what());
    }
    lock.lock();
    wake_.wait_for(lock, lease_.check_every(), [&] { return stop_; });
  }
}

}  // namespace lorgnette::service
