// A team of threads for the loops of one solve: the caller and threads - 1 workers take the
// chunks of a range in turn. Waiting spins for a bounded time, then sleeps: with more threads than free
// cores (other processes, other teams), spinning workers would take the cores from the ones
// with work (an OpenMP runtime's spinning barriers made a sweep many times slower there).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace frix {

class ThreadTeam {
   public:
    explicit ThreadTeam(int threads) {
        for (int k = 1; k < threads; ++k) workers_.emplace_back([this] { work(); });
    }
    ~ThreadTeam() {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
            generation_.fetch_add(1, std::memory_order_release);
        }
        wake_.notify_all();
        for (std::thread &t : workers_) t.join();
    }
    ThreadTeam(const ThreadTeam &) = delete;
    ThreadTeam &operator=(const ThreadTeam &) = delete;

    int size() const { return (int)workers_.size() + 1; }

    // body(begin, end) over [0, n) in chunks of `chunk`, each taken by whichever thread is free
    // (the caller too); returns when every chunk is done. Which thread runs a chunk must not
    // change the result. A range of one chunk runs on the caller alone; a chunk should be
    // work enough to outweigh waking a thread (tens of microseconds).
    void for_chunks(int64_t n, int64_t chunk, const std::function<void(int64_t, int64_t)> &body) {
        if (workers_.empty() || n <= chunk) {
            if (n > 0) body(0, n);
            return;
        }
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            body_ = &body;
            n_ = n;
            chunk_ = chunk;
            next_.store(0, std::memory_order_relaxed);
            busy_.store((int)workers_.size(), std::memory_order_relaxed);
            generation_.fetch_add(1, std::memory_order_release);
        }
        wake_.notify_all();
        take_chunks();
        // The workers' ends: spin a while, then sleep until the last one says so.
        const auto finished = [this] { return busy_.load(std::memory_order_acquire) == 0; };
        if (!spin_until(finished)) {
            std::unique_lock<std::mutex> lock(mutex_);
            done_.wait(lock, finished);
        }
        body_ = nullptr;
    }

    // body(t) once on each thread t of the team (the caller is t = 0), all at once: a body may
    // wait for another's progress (a pipeline). Returns when every body has returned.
    void for_each_thread(const std::function<void(int64_t)> &body) {
        if (workers_.empty()) {
            body(0);
            return;
        }
        const std::function<void(int64_t, int64_t)> chunks = [&body](int64_t begin, int64_t) { body(begin); };
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            body_ = &chunks;
            n_ = size();
            chunk_ = 1;
            // The caller runs body(0) itself and takes no other: a worker takes one index, and
            // another only once that body returned, so no body waits on one queued behind it.
            next_.store(1, std::memory_order_relaxed);
            busy_.store((int)workers_.size(), std::memory_order_relaxed);
            generation_.fetch_add(1, std::memory_order_release);
        }
        wake_.notify_all();
        body(0);
        const auto finished = [this] { return busy_.load(std::memory_order_acquire) == 0; };
        if (!spin_until(finished)) {
            std::unique_lock<std::mutex> lock(mutex_);
            done_.wait(lock, finished);
        }
        body_ = nullptr;
    }

   private:
    // How long a waiting thread spins before it sleeps: about one chunk of a sweep's work,
    // so that a thread that ends its share a little early is not put to sleep and woken (tens
    // of microseconds each) between two ranges run back to back.
    static constexpr std::chrono::microseconds kSpinTime{100};

    // Whether ready() became true within kSpinTime.
    template <class Ready>
    static bool spin_until(const Ready &ready) {
        const auto until = std::chrono::steady_clock::now() + kSpinTime;
        for (int k = 1;; ++k) {
            if (ready()) return true;
            if (k % 64 == 0 && std::chrono::steady_clock::now() > until) return false;
        }
    }

    void take_chunks() {
        for (;;) {
            const int64_t begin = next_.fetch_add(chunk_, std::memory_order_relaxed);
            if (begin >= n_) return;
            (*body_)(begin, begin + chunk_ < n_ ? begin + chunk_ : n_);
        }
    }

    void work() {
        uint64_t seen = 0;
        for (;;) {
            // A new job: spin a while, then sleep until one comes.
            const auto job = [&] { return generation_.load(std::memory_order_acquire) != seen; };
            if (!spin_until(job)) {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, job);
            }
            {
                const std::lock_guard<std::mutex> lock(mutex_);
                seen = generation_.load(std::memory_order_acquire);
                if (stop_) return;
            }
            take_chunks();
            if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
                const std::lock_guard<std::mutex> lock(mutex_);  // the caller may be going to sleep
                done_.notify_one();
            }
        }
    }

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::atomic<uint64_t> generation_{0};
    std::atomic<int64_t> next_{0};
    std::atomic<int> busy_{0};
    bool stop_ = false;
    const std::function<void(int64_t, int64_t)> *body_ = nullptr;
    int64_t n_ = 0, chunk_ = 1;
};

}  // namespace frix
