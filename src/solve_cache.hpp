// What a persistent solver (frix_persistent) keeps between solves, for the solvers to reuse:
// each solver family stores its own state (symbolic analyses, factorisations, workspaces)
// under its solver id, and checks the versions of the local W it was built from before using
// it. A one-shot frix_solve passes no cache, and every solver must work without one.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

namespace frix {

// The base of every kept state; a solver downcasts to its own type (states are keyed by the
// solver id, so the type under a key is always the one its solver stored).
struct CachedState {
    virtual ~CachedState() = default;
};

class SolveCache {
   public:
    // The local W the solvers see (the caller's, or H^T M^-1 H formed by the driver):
    // w_values changes whenever its values may have changed, w_pattern whenever its sparsity
    // pattern did. A state built at the same versions may reuse everything computed from W.
    uint64_t w_values = 1, w_pattern = 1;
    // Global problems: the versions of M's and H's values (changed by every update of them).
    uint64_t m_values = 1, h_values = 1;

    // The state kept under `key`, taken out (null if there is none, or if another stage of
    // auto holds it right now): the taker has it to itself until it gives it back.
    std::unique_ptr<CachedState> take(int key) {
        const std::lock_guard<std::mutex> lock(mutex_);
        auto it = states_.find(key);
        if (it == states_.end()) return nullptr;
        std::unique_ptr<CachedState> s = std::move(it->second);
        states_.erase(it);
        return s;
    }
    // Keeps `state` under `key` for the next solve (replacing what may be there).
    void give_back(int key, std::unique_ptr<CachedState> state) {
        const std::lock_guard<std::mutex> lock(mutex_);
        states_[key] = std::move(state);
    }
    void clear() {
        const std::lock_guard<std::mutex> lock(mutex_);
        states_.clear();
    }

   private:
    std::mutex mutex_;  // auto's stages may take and give back from several threads
    std::map<int, std::unique_ptr<CachedState>> states_;
};

// A solver's state of type T for one solve: the one kept under `key` when there is a cache and
// it holds one, a new one otherwise. Given back to the cache at the end of the solve only if
// keep() was called: a solve that failed part-way may leave its state half-built.
template <class T>
class Kept {
   public:
    Kept(SolveCache *cache, int key) : cache_(cache), key_(key) {
        if (cache_) {
            std::unique_ptr<CachedState> s = cache_->take(key_);
            if (s) {
                state_.reset(static_cast<T *>(s.release()));
                reused_ = true;
            }
        }
        if (!state_) state_ = std::make_unique<T>();
    }
    ~Kept() {
        if (cache_ && keep_) cache_->give_back(key_, std::move(state_));
    }
    Kept(const Kept &) = delete;
    Kept &operator=(const Kept &) = delete;
    T &operator*() { return *state_; }
    T *operator->() { return state_.get(); }
    // Whether the state comes from an earlier solve.
    bool reused() const { return reused_; }
    void keep() { keep_ = true; }

   private:
    SolveCache *cache_;
    int key_;
    std::unique_ptr<T> state_;
    bool reused_ = false;
    bool keep_ = false;
};

}  // namespace frix
