// Per-address connection slots, a throttled log and the accept backoff (connection_limits.h).
#include "viewer/connection_limits.h"

#include <algorithm>

namespace lorgnette::viewer {

AddressLimit::Slot& AddressLimit::Slot::operator=(Slot&& o) noexcept {
  if (this != &o) {
    release();
    counts_ = std::move(o.counts_);
    address_ = std::move(o.address_);
  }
  return *this;
}

void AddressLimit::Slot::release() {
  if (!counts_) return;
  {
    std::lock_guard<std::mutex> lock(counts_->m);
    auto it = counts_->open.find(address_);
    if (it != counts_->open.end() && --it->second == 0) counts_->open.erase(it);
  }
  counts_.reset();
}

AddressLimit::Slot AddressLimit::acquire(const std::string& address) {
  std::lock_guard<std::mutex> lock(counts_->m);
  size_t& n = counts_->open[address];
  if (n >= max_) {
    if (n == 0) counts_->open.erase(address);
    return {};
  }
  ++n;
  return Slot(counts_, address);
}

size_t AddressLimit::open(const std::string& address) const {
  std::lock_guard<std::mutex> lock(counts_->m);
  auto it = counts_->open.find(address);
  return it == counts_->open.end() ? 0 : it->second;
}

std::optional<size_t> ThrottledLog::admit(Clock::time_point now) {
  if (last_ && now - *last_ < interval_) {
    ++held_back_;
    return std::nullopt;
  }
  last_ = now;
  size_t held = held_back_;
  held_back_ = 0;
  return held;
}

std::chrono::milliseconds Backoff::next() {
  current_ = current_.count() == 0 ? first_ : std::min(current_ * 2, max_);
  return current_;
}

}  // namespace lorgnette::viewer
