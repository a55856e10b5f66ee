// distributed.cpp: rendezvous over c10d's TCPStore, then Gloo collectives on flattened buckets.
// Every failure of the group becomes one ltm::Error line that names this rank, so a user of a
// lost or misconfigured rank reads what happened instead of a Gloo backtrace or a hang.
#include "ltm/train/distributed.h"

#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <thread>

#ifdef LTM_HAVE_GLOO
#include <torch/csrc/distributed/c10d/PrefixStore.hpp>
#include <torch/csrc/distributed/c10d/ProcessGroupGloo.hpp>
#include <torch/csrc/distributed/c10d/TCPStore.hpp>
#endif

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/nn/torch_runtime.h"

namespace ltm {

#ifdef LTM_HAVE_GLOO
namespace {

std::vector<uint8_t> bytes(const std::string &s) { return {s.begin(), s.end()}; }
std::string text(const std::vector<uint8_t> &b) { return {b.begin(), b.end()}; }

bool is_loopback(const std::string &addr) { return addr == "localhost" || addr.rfind("127.", 0) == 0 || addr == "::1"; }

// What a rank announces: "W|fingerprint".
std::string announcement(int world_size, const std::string &fingerprint) { return std::to_string(world_size) + "|" + fingerprint; }

// "" when `theirs` (rank r's announcement) agrees with `ours`, else why not.
std::string disagreement(int r, const std::string &theirs, int our_rank, const std::string &ours) {
    const size_t a = theirs.find('|'), b = ours.find('|');
    if (theirs.substr(0, a) != ours.substr(0, b))
        return "rank " + std::to_string(r) + " has WORLD_SIZE " + theirs.substr(0, a) + ", rank " + std::to_string(our_rank) +
               " has " + ours.substr(0, b);
    if (theirs != ours)
        return "rank " + std::to_string(r) + " trains another model config, training config or dataset than rank " +
               std::to_string(our_rank) + " (fingerprint " + theirs.substr(a + 1) + " vs " + ours.substr(b + 1) + ")";
    return "";
}

// Waits until a TCP connection to host:port succeeds (the master is up) or the timeout passes.
// c10d's client would find out too, but it logs through glog on the way (a second, multi-line
// message); checking first keeps an unreachable master a one-line error.
bool reachable(const std::string &host, int port, double timeout_s) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    do {
        addrinfo hints{}, *res = nullptr;
        hints.ai_family = AF_UNSPEC;
        hints.ai_socktype = SOCK_STREAM;
        if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &res) == 0) {
            bool ok = false;
            for (addrinfo *a = res; a && !ok; a = a->ai_next) {
                const int fd = ::socket(a->ai_family, a->ai_socktype, a->ai_protocol);
                if (fd < 0) continue;
                ok = ::connect(fd, a->ai_addr, a->ai_addrlen) == 0;
                ::close(fd);
            }
            ::freeaddrinfo(res);
            if (ok) return true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    } while (std::chrono::steady_clock::now() < end);
    return false;
}

}  // namespace
#endif

#ifdef LTM_HAVE_GLOO
struct Communicator::Impl {
    c10::intrusive_ptr<c10d::Store> store;
    c10::intrusive_ptr<c10d::ProcessGroupGloo> group;
};
#else
struct Communicator::Impl {};
#endif

Communicator::Communicator(const DistSettings &s, const std::string &fingerprint) : m_settings(s) {
    const std::string id = who();
    if (s.world_size < 1) LTM_THROW("WORLD_SIZE ", s.world_size, ": must be >= 1");
    if (s.rank < 0 || s.rank >= s.world_size) LTM_THROW("RANK ", s.rank, ": must be in [0, WORLD_SIZE = ", s.world_size, ")");
    if (s.master_port < 1 || s.master_port > 65535) LTM_THROW("MASTER_PORT ", s.master_port, ": must be in [1, 65535]");
    if (!(s.timeout_s > 0)) LTM_THROW("distributed timeout ", s.timeout_s, " s: must be > 0");
    if (s.world_size == 1) return;
#ifndef LTM_HAVE_GLOO
    (void)fingerprint;
    LTM_THROW(id, ": this build has no data-parallel backend (built without the gloo headers: install libgloo-dev and rebuild)");
#else
    const auto timeout = std::chrono::milliseconds(int64_t(s.timeout_s * 1000.0));
    m_impl = std::make_unique<Impl>();
    const std::string master = s.master_addr + ":" + std::to_string(s.master_port);
    if (s.rank != 0 && !reachable(s.master_addr, s.master_port, s.timeout_s))
        LTM_THROW(id, ": cannot reach the rendezvous at MASTER_ADDR:MASTER_PORT = ", master, " within ", s.timeout_s,
                  " s (is rank 0 running, and the address right?)");
    try {
        c10d::TCPStoreOptions o;
        o.port = uint16_t(s.master_port);
        o.isServer = s.rank == 0;
        o.waitWorkers = false;   // ranks are counted below, with errors that say who is missing
        o.timeout = timeout;
        m_impl->store = c10::make_intrusive<c10d::TCPStore>(s.master_addr, o);
    } catch (const std::exception &e) {
        LTM_THROW(id, ": cannot ", s.rank == 0 ? "serve" : "reach", " the rendezvous at MASTER_ADDR:MASTER_PORT = ", master,
                  " within ", s.timeout_s, " s (", exception_line(e), ")");
    }
    c10d::Store &store = *m_impl->store;
    const std::string ours = announcement(s.world_size, fingerprint);
    try {
        if (store.add("ltm/claim/" + std::to_string(s.rank), 1) > 1)
            LTM_THROW(id, ": another process already joined as rank ", s.rank, " (is RANK unique per process?)");
        store.set("ltm/rank/" + std::to_string(s.rank), bytes(ours));
        if (s.rank == 0) {
            // Rank 0 checks every rank against itself and publishes the verdict.
            std::vector<std::string> keys;
            for (int r = 0; r < s.world_size; ++r) keys.push_back("ltm/rank/" + std::to_string(r));
            try {
                store.wait(keys, timeout);
            } catch (const std::exception &) {
                std::string missing;
                for (int r = 1; r < s.world_size; ++r)
                    if (!store.check({keys[size_t(r)]})) missing += (missing.empty() ? "" : ", ") + std::to_string(r);
                const std::string why = "rank(s) " + missing + " did not join within " + std::to_string(int(s.timeout_s)) +
                                        " s (same WORLD_SIZE on every rank? every rank started?)";
                store.set("ltm/verdict", bytes(why));
                LTM_THROW(id, ": ", why);
            }
            std::string verdict;
            for (int r = 1; r < s.world_size && verdict.empty(); ++r) verdict = disagreement(r, text(store.get(keys[size_t(r)])), 0, ours);
            store.set("ltm/verdict", bytes(verdict.empty() ? "ok" : verdict));
            if (!verdict.empty()) {
                // Keep serving the store until the others have read the verdict (a few seconds at
                // most): closing it at once would leave them a "connection reset" instead.
                const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
                while (store.add("ltm/seen", 0) < s.world_size - 1 && std::chrono::steady_clock::now() < until)
                    std::this_thread::sleep_for(std::chrono::milliseconds(20));
                LTM_THROW(id, ": ", verdict);
            }
        } else {
            const std::string verdict = text(store.get("ltm/verdict"));   // waits for rank 0's
            store.add("ltm/seen", 1);
            if (verdict != "ok") LTM_THROW(id, ": ", verdict);
            // A rank beyond rank 0's WORLD_SIZE is not in rank 0's check: compare with it here.
            const std::string why = disagreement(0, text(store.get("ltm/rank/0")), s.rank, ours);
            if (!why.empty()) LTM_THROW(id, ": ", why);
        }
        auto opts = c10d::ProcessGroupGloo::Options::create(timeout);
        opts->devices.push_back(is_loopback(s.master_addr) ? c10d::ProcessGroupGloo::createDeviceForHostname("127.0.0.1")
                                                           : c10d::ProcessGroupGloo::createDefaultDevice());
        opts->threads = 1;
        m_impl->group = c10::make_intrusive<c10d::ProcessGroupGloo>(c10::make_intrusive<c10d::PrefixStore>("ltm/gloo", m_impl->store),
                                                                    s.rank, s.world_size, opts);
    } catch (const Error &) {
        throw;
    } catch (const std::exception &e) {
        LTM_THROW(id, ": rendezvous at ", master, " failed (", exception_line(e), ")");
    }
    log_info(id, ": joined the group at ", master);
#endif
}

Communicator::~Communicator() = default;

std::string Communicator::who() const { return "rank " + std::to_string(rank()) + "/" + std::to_string(world_size()); }

#ifdef LTM_HAVE_GLOO
namespace {
// Runs one collective over `tensors` bucket by bucket: each bucket is flattened into one buffer,
// start(buffers) issues the collective on it, its completion is awaited (a failure becomes one
// line naming `who` and `what`), and the buffer is copied back.
template <class Start>
void bucketed(const std::vector<torch::Tensor> &tensors, int64_t bucket_elements, const std::string &who, const char *what,
              const Start &start) {
    size_t i = 0;
    while (i < tensors.size()) {
        size_t j = i;
        int64_t n = 0;
        while (j < tensors.size() && (j == i || n + tensors[j].numel() <= bucket_elements)) n += tensors[j++].numel();
        std::vector<torch::Tensor> flat_parts;
        for (size_t k = i; k < j; ++k) {
            LTM_CHECK(tensors[k].device().is_cpu() && tensors[k].scalar_type() == tensors[i].scalar_type());
            flat_parts.push_back(tensors[k].reshape({-1}));
        }
        std::vector<torch::Tensor> flat{torch::cat(flat_parts)};
        try {
            start(flat)->wait();
        } catch (const std::exception &e) {
            LTM_THROW(who, ": ", what, " failed — a peer exited or stopped answering (", exception_line(e), ")");
        }
        int64_t off = 0;
        for (size_t k = i; k < j; ++k) {
            const int64_t m = tensors[k].numel();
            tensors[k].view({-1}).copy_(flat[0].slice(0, off, off + m));
            off += m;
        }
        i = j;
    }
}
}  // namespace
#endif

void Communicator::all_reduce_sum(const std::vector<torch::Tensor> &tensors, int64_t bucket_elements) {
    if (!m_impl) return;
#ifdef LTM_HAVE_GLOO
    bucketed(tensors, bucket_elements, who(), "all-reduce", [&](std::vector<torch::Tensor> &flat) { return m_impl->group->allreduce(flat); });
#else
    (void)tensors, (void)bucket_elements;
#endif
}

void Communicator::broadcast_from_root(const std::vector<torch::Tensor> &tensors, int64_t bucket_elements) {
    if (!m_impl) return;
#ifdef LTM_HAVE_GLOO
    c10d::BroadcastOptions o;
    o.rootRank = 0;
    bucketed(tensors, bucket_elements, who(), "broadcast", [&](std::vector<torch::Tensor> &flat) { return m_impl->group->broadcast(flat, o); });
#else
    (void)tensors, (void)bucket_elements;
#endif
}

std::vector<double> Communicator::all_reduce_sum(const std::vector<double> &values) {
    if (!m_impl || values.empty()) return values;
    auto t = torch::tensor(values, torch::kFloat64);
    all_reduce_sum(std::vector<torch::Tensor>{t});
    return {t.data_ptr<double>(), t.data_ptr<double>() + t.numel()};
}

bool data_parallel_available() {
#ifdef LTM_HAVE_GLOO
    return true;
#else
    return false;
#endif
}

std::string fingerprint_of(const std::string &s) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ull;
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
    return buf;
}

}  // namespace ltm
