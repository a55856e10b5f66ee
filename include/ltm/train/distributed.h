// distributed.h: data-parallel training across processes with libtorch's own c10d — the
// rendezvous (a TCP key-value store served by rank 0), a consistency check of what every rank is
// about to train, and the collectives the trainer needs (Gloo on CPU tensors). libtorch's C++ API
// has no DistributedDataParallel: the trainer all-reduces its gradients itself, in buckets.
//
// The launcher contract is torchrun's (RANK, WORLD_SIZE, LOCAL_RANK, MASTER_ADDR, MASTER_PORT);
// the CLI reads those variables and fills DistSettings — this library reads no environment.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <torch/torch.h>

namespace ltm {

struct DistSettings {
    int rank = 0, world_size = 1, local_rank = 0;
    std::string master_addr = "127.0.0.1";
    int master_port = 29500;
    /// Limit for the rendezvous (every rank joined) and for each collective. A peer that dies
    /// closes its sockets, which fails the others' collectives at once; the limit catches a
    /// peer that hangs.
    double timeout_s = 300.0;
};

/// One process's membership of the group. world_size 1 is a group of one: every collective is
/// the identity and nothing is opened.
class Communicator {
public:
    /// Joins the group: rank 0 serves the store at master_addr:master_port, every rank announces
    /// (world_size, fingerprint) and waits for all ranks. Throws ltm::Error, naming the rank and
    /// the cause, when the master is unreachable, a rank does not join within the timeout, two
    /// processes claim one rank, or a rank's world size or fingerprint differs from rank 0's.
    /// `fingerprint` is what must agree: e.g. the model and training configs and the data's seeds.
    Communicator(const DistSettings &settings, const std::string &fingerprint);
    ~Communicator();
    Communicator(const Communicator &) = delete;
    Communicator &operator=(const Communicator &) = delete;

    int rank() const { return m_settings.rank; }
    int world_size() const { return m_settings.world_size; }
    bool is_root() const { return m_settings.rank == 0; }

    /// Sums the tensors over all ranks, in place. Contiguous CPU tensors of one floating dtype;
    /// they travel flattened into buckets of at most bucket_elements (one collective per bucket).
    ///   tensors: any shapes, the same list (count, shapes, order) on every rank
    void all_reduce_sum(const std::vector<torch::Tensor> &tensors, int64_t bucket_elements = int64_t(1) << 22);
    /// Copies rank 0's values into every rank's tensors, in place (same contract as above).
    void broadcast_from_root(const std::vector<torch::Tensor> &tensors, int64_t bucket_elements = int64_t(1) << 22);
    /// Sums a few doubles over all ranks (validation sums, the step's loss).
    std::vector<double> all_reduce_sum(const std::vector<double> &values);

private:
    std::string who() const;   ///< "rank r/W", the prefix of every error
    struct Impl;
    DistSettings m_settings;
    std::unique_ptr<Impl> m_impl;
};

/// Whether this build has a data-parallel backend (Gloo headers found at configure time).
bool data_parallel_available();

/// 16 hex digits of FNV-1a over `text`: a short, stable fingerprint for the rendezvous check.
std::string fingerprint_of(const std::string &text);

}  // namespace ltm
