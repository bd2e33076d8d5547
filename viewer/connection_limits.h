// What keeps one misbehaving peer from taking the viewer from everyone else: a count of open
// connections per remote address with a maximum (a slot is held for a connection's whole life, HTTP
// and WebSocket alike), a message that is logged at most once per interval (with how many were held
// back), and the growing pause between failed accepts (out of file descriptors, the listening
// socket stays readable: retrying at once would spin a core and flood the log).
#pragma once
#include <chrono>
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace lorgnette::viewer {

class AddressLimit {
  struct Counts {
    std::mutex m;
    std::map<std::string, size_t> open;
  };

 public:
  // One open connection of an address; releases it when destroyed. Move-only.
  class Slot {
   public:
    Slot() = default;
    Slot(Slot&& o) noexcept : counts_(std::move(o.counts_)), address_(std::move(o.address_)) {}
    Slot& operator=(Slot&& o) noexcept;
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;
    ~Slot() { release(); }
    explicit operator bool() const { return counts_ != nullptr; }

   private:
    friend class AddressLimit;
    Slot(std::shared_ptr<Counts> c, std::string a) : counts_(std::move(c)), address_(std::move(a)) {}
    void release();
    std::shared_ptr<Counts> counts_;
    std::string address_;
  };

  explicit AddressLimit(size_t max_per_address) : max_(max_per_address) {}
  // A slot for `address`, or an empty one when the address already holds the maximum.
  Slot acquire(const std::string& address);
  size_t open(const std::string& address) const;

 private:
  size_t max_;
  std::shared_ptr<Counts> counts_ = std::make_shared<Counts>();
};

// admit() is true at most once per interval; held_back() then says how many calls it refused since.
class ThrottledLog {
 public:
  using Clock = std::chrono::steady_clock;
  explicit ThrottledLog(Clock::duration interval) : interval_(interval) {}
  // The number of messages held back since the last one when this one may be logged.
  std::optional<size_t> admit(Clock::time_point now = Clock::now());

 private:
  Clock::duration interval_;
  std::optional<Clock::time_point> last_;
  size_t held_back_ = 0;
};

// The pause before the next accept after a failure: `first`, doubling up to `max`; reset() after a
// success.
class Backoff {
 public:
  Backoff(std::chrono::milliseconds first, std::chrono::milliseconds max) : first_(first), max_(max) {}
  std::chrono::milliseconds next();
  void reset() { current_ = std::chrono::milliseconds(0); }

 private:
  std::chrono::milliseconds first_, max_, current_{0};
};

}  // namespace lorgnette::viewer
