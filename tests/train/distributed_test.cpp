// distributed_test.cpp: data-parallel training on loopback. In one process (two threads, two
// ranks): 2 ranks × 1 scene train the parameters 1 process × a 2-scene batch trains, and the
// rendezvous refuses mismatched groups with errors that say why. As processes (the ltm binary):
// `--nproc 2` and a resume with another world size continue one run; a rank killed with SIGKILL
// makes the other exit with an error instead of hanging, and --resume then loses at most one
// checkpoint interval.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/train/distributed.h"
#include "ltm/train/trainer.h"
#include "rank_launcher.h"
#include "small_dataset.h"
#include "test_util.h"

extern char **environ;

using namespace ltm;
namespace fs = std::filesystem;

namespace {

const std::string &dataset_dir() {
    static const std::string dir = test::build_small_dataset("ltm_distributed_test_data", {21, 22, 23}, 1024, 16);
    static const test::RemoveAtExit cleanup{dir};
    return dir;
}

TrainConfig two_scene_steps(int steps, int ranks = 1) {
    // Per rank: W ranks × (2/W scenes, 512/W queries) = one process × (2 scenes, 512 queries).
    TrainConfig t;
    t.steps = steps, t.scenes_per_step = 2 / ranks, t.batch_queries = 512 / ranks;
    t.lr = 1e-3f, t.warmup_steps = 1;
    t.val_every = 1000, t.ckpt_every = 1000, t.log_every = 1000;
    t.val_fraction = 0.34f;   // 2 records train, 1 validates
    return t;
}

ModelConfig tiny() { return ModelConfig::from_file(test::source_path("configs/model/tiny.json")); }

DistSettings rank_settings(int rank, int world, int port, double timeout_s = 30.0) {
    DistSettings s;
    s.rank = rank, s.world_size = world, s.master_port = port, s.timeout_s = timeout_s;
    return s;
}

// Joins ranks 0..n-1 concurrently (the constructor blocks until all have joined).
std::vector<std::shared_ptr<Communicator>> join(int n, int port, const std::vector<std::string> &fingerprints) {
    std::vector<std::future<std::shared_ptr<Communicator>>> f;
    for (int r = 0; r < n; ++r)
        f.push_back(std::async(std::launch::async, [=] { return std::make_shared<Communicator>(rank_settings(r, n, port), fingerprints[size_t(r)]); }));
    std::vector<std::shared_ptr<Communicator>> out;
    for (auto &x : f) out.push_back(x.get());
    return out;
}

// Runs the ltm binary with `args` and extra environment; stderr to `err_path`. Returns the pid.
pid_t spawn_ltm(const std::vector<std::string> &args, const std::vector<std::string> &env_extra, const std::string &err_path) {
    std::vector<std::string> argv_s = {LTM_BINARY};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char *> argv;
    for (auto &a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_s;
    for (char **e = environ; *e; ++e) env_s.emplace_back(*e);
    env_s.insert(env_s.end(), env_extra.begin(), env_extra.end());
    std::vector<char *> envp;
    for (auto &v : env_s) envp.push_back(v.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) ADD_FAILURE() << "posix_spawn " << LTM_BINARY << " failed: " << rc;
    return pid;
}

// waitpid with a deadline: the exit status, or -1 if the process is still running at the deadline.
int wait_for(pid_t pid, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        int status = 0;
        if (::waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return -1;
}

std::vector<double> logged_losses(const std::string &log_path) {
    std::vector<double> out;
    std::ifstream in(log_path);
    std::string line;
    while (std::getline(in, line)) {
        const Json j = parse_json(line, log_path);
        if (j.contains("loss")) out.push_back(j["loss"].get<double>());
    }
    return out;
}

// The run's per-rank batch: `ranks` × (2/ranks scenes, 512/ranks queries) is one process's 2 × 512.
std::vector<std::string> train_args(const std::string &out, int steps, int ranks = 1) {
    return {"train", "--model", test::source_path("configs/model/tiny.json"), "--data", dataset_dir(), "--out", out,
            "--steps", std::to_string(steps), "--set", "scenes_per_step=" + std::to_string(2 / ranks), "--set",
            "batch_queries=" + std::to_string(512 / ranks), "--set", "log_every=1",
            "--set", "val_every=1000", "--set", "lr=1e-3", "--set", "warmup_steps=1", "--set", "val_fraction=0.34",
            "--threads", "1", "-q"};
}

}  // namespace

TEST(Distributed, TwoRanksTrainTheParametersOfOneProcessWithTheJointBatch) {
    if (!data_parallel_available()) GTEST_SKIP() << "built without gloo";
    test::TempDir dir;
    Trainer single(tiny(), two_scene_steps(5), {dataset_dir()}, dir.path("single"));
    single.run(false);

    Trainer r0(tiny(), two_scene_steps(5, 2), {dataset_dir()}, dir.path("rank0"));
    Trainer r1(tiny(), two_scene_steps(5, 2), {dataset_dir()}, dir.path("rank1"));
    const auto comms = join(2, cli::free_local_port(), {r0.fingerprint(), r1.fingerprint()});
    r0.set_communicator(comms[0]);
    r1.set_communicator(comms[1]);
    auto a = std::async(std::launch::async, [&] { r0.run(false); });
    auto b = std::async(std::launch::async, [&] { r1.run(false); });
    a.get(), b.get();

    ASSERT_EQ(r0.history().size(), 5u);
    for (size_t i = 0; i < 5; ++i) EXPECT_NEAR(r0.history()[i].loss, single.history()[i].loss, 1e-6 * single.history()[i].loss);
    const auto ps = single.model()->named_parameters(), p0 = r0.model()->named_parameters(), p1 = r1.model()->named_parameters();
    double moved = 0;
    Trainer fresh(tiny(), two_scene_steps(5), {dataset_dir()}, dir.path("fresh"));
    auto pf = fresh.model()->named_parameters();
    for (const auto &p : ps) {
        const auto &ref = p.value();
        const double scale = ref.abs().max().item<double>() + 1e-12;
        EXPECT_LE((p0[p.key()] - ref).abs().max().item<double>(), 1e-5 * scale) << p.key();
        EXPECT_TRUE(torch::equal(p0[p.key()], p1[p.key()])) << p.key() << ": the ranks drifted apart";
        moved = std::max(moved, (ref - pf[p.key()]).abs().max().item<double>());
    }
    EXPECT_GT(moved, 1e-4);   // training changed the weights: the comparison is not of initialisations
    // Rank 0 alone writes the run.
    EXPECT_TRUE(fs::exists(dir.path("rank0/last.ltmckpt")));
    EXPECT_FALSE(fs::exists(dir.path("rank1/last.ltmckpt")));
    EXPECT_FALSE(fs::exists(dir.path("rank1/log.jsonl")));
}

TEST(Distributed, MismatchedGroupsAreRefusedWithTheReason) {
    if (!data_parallel_available()) GTEST_SKIP() << "built without gloo";
    // Different configs (fingerprints): both ranks say so.
    {
        const int port = cli::free_local_port();
        auto f0 = std::async(std::launch::async, [&] { Communicator c(rank_settings(0, 2, port), "aaaa"); });
        auto f1 = std::async(std::launch::async, [&] { Communicator c(rank_settings(1, 2, port), "bbbb"); });
        for (auto *f : {&f0, &f1}) {
            try {
                f->get();
                ADD_FAILURE() << "a rank joined a group with another config";
            } catch (const Error &e) {
                EXPECT_NE(std::string(e.what()).find("another model config"), std::string::npos) << e.what();
            }
        }
    }
    // Different WORLD_SIZE: rank 0 (2) names rank 1's (3).
    {
        const int port = cli::free_local_port();
        auto f0 = std::async(std::launch::async, [&] { Communicator c(rank_settings(0, 2, port, 10.0), "f"); });
        auto f1 = std::async(std::launch::async, [&] { Communicator c(rank_settings(1, 3, port, 10.0), "f"); });
        try {
            f0.get();
            ADD_FAILURE();
        } catch (const Error &e) {
            EXPECT_NE(std::string(e.what()).find("WORLD_SIZE 3"), std::string::npos) << e.what();
        }
        EXPECT_THROW(f1.get(), Error);
    }
    // Nobody serves the rendezvous: an error within about the timeout, naming the address.
    {
        const auto t0 = std::chrono::steady_clock::now();
        try {
            Communicator c(rank_settings(1, 2, cli::free_local_port(), 2.0), "f");
            ADD_FAILURE();
        } catch (const Error &e) {
            EXPECT_NE(std::string(e.what()).find("cannot reach"), std::string::npos) << e.what();
        }
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30.0);
    }
    EXPECT_THROW(Communicator(rank_settings(2, 2, 29500), "f"), Error);   // RANK outside [0, WORLD_SIZE)
}

// `ltm train --nproc 2` for 3 steps, then one process resumes it to 6: the losses of one
// uninterrupted single-process run with the same 2-scene batch (constant lr after warm-up, so
// the schedule does not depend on --steps).
TEST(Distributed, NprocRunResumesInOneProcess) {
    if (!data_parallel_available()) GTEST_SKIP() << "built without gloo";
    test::TempDir dir;
    const std::string err = dir.path("err.txt");
    auto args = [&](const std::string &out, int steps, int ranks = 1) {
        auto a = train_args(dir.path(out), steps, ranks);
        a.insert(a.end(), {"--set", "min_lr_ratio=1"});
        return a;
    };
    ASSERT_EQ(wait_for(spawn_ltm(args("single", 6), {}, err), 300), 0) << read_file(err);
    auto two = args("dp", 3, 2);   // 2 ranks × (1 scene, 256 queries)
    *(std::find(two.begin(), two.end(), "--threads") + 1) = "2";   // one thread per rank
    two.insert(two.end(), {"--nproc", "2"});
    ASSERT_EQ(wait_for(spawn_ltm(two, {}, err), 300), 0) << read_file(err);
    EXPECT_EQ(logged_losses(dir.path("dp/log.jsonl")).size(), 3u);
    auto resume = args("dp", 6);   // one process × (2 scenes, 512 queries): the same global batch
    resume.push_back("--resume");
    ASSERT_EQ(wait_for(spawn_ltm(resume, {}, err), 300), 0) << read_file(err);
    const auto a = logged_losses(dir.path("single/log.jsonl")), b = logged_losses(dir.path("dp/log.jsonl"));
    ASSERT_EQ(a.size(), 6u);
    ASSERT_EQ(b.size(), 6u);
    for (size_t i = 0; i < 6; ++i) EXPECT_NEAR(a[i], b[i], 1e-5 * a[i]) << "step " << i;
    // The default config (1 scene and 8192 queries per rank) trains with any --nproc: 3 ranks, 1 step.
    const std::vector<std::string> three = {"train", "--model", test::source_path("configs/model/tiny.json"), "--data", dataset_dir(),
                                            "--out", dir.path("three"), "--steps", "1", "--set", "val_every=1000", "--set",
                                            "val_fraction=0.34", "--threads", "3", "--nproc", "3", "-q"};
    ASSERT_EQ(wait_for(spawn_ltm(three, {}, err), 300), 0) << read_file(err);
    EXPECT_EQ(logged_losses(dir.path("three/log.jsonl")).size(), 1u);
}

// SIGKILL one of two ranks mid-run: the survivor exits with an error (no hang) well within 60 s,
// and a resume (one process) continues from the last checkpoint, at most ckpt_every steps back.
TEST(Distributed, ALostRankEndsTheGroupAndTheRunResumes) {
    if (!data_parallel_available()) GTEST_SKIP() << "built without gloo";
    test::TempDir dir;
    const int port = cli::free_local_port();
    auto args = train_args(dir.path("run"), 400, 2);
    args.insert(args.end(), {"--set", "ckpt_every=2", "--dist-timeout", "120"});
    auto env = [&](int r) {
        return std::vector<std::string>{"RANK=" + std::to_string(r), "WORLD_SIZE=2", "LOCAL_RANK=" + std::to_string(r),
                                        "MASTER_ADDR=127.0.0.1", "MASTER_PORT=" + std::to_string(port)};
    };
    const pid_t p0 = spawn_ltm(args, env(0), dir.path("err0.txt")), p1 = spawn_ltm(args, env(1), dir.path("err1.txt"));
    // Wait until a few steps (and a checkpoint) are done.
    const auto start = std::chrono::steady_clock::now();
    while (logged_losses(dir.path("run/log.jsonl")).size() < 5 && std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ASSERT_GE(logged_losses(dir.path("run/log.jsonl")).size(), 5u) << read_file(dir.path("err0.txt"));
    ::kill(p1, SIGKILL);
    const auto killed_at = std::chrono::steady_clock::now();
    const int rc = wait_for(p0, 60);
    if (rc < 0) ::kill(p0, SIGKILL), ::waitpid(p0, nullptr, 0);
    ::waitpid(p1, nullptr, 0);
    EXPECT_EQ(rc, 1) << "the surviving rank must exit with an error, not hang";
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - killed_at).count(), 60.0);
    const std::string e0 = read_file(dir.path("err0.txt"));
    EXPECT_NE(e0.find("rank 0/2"), std::string::npos) << e0;
    EXPECT_EQ(std::count(e0.begin(), e0.end(), '\n'), 1) << "one line: " << e0;
    const size_t logged = logged_losses(dir.path("run/log.jsonl")).size();
    const int64_t ckpt_step = read_checkpoint_state(dir.path("run/last.ltmckpt")).step;
    EXPECT_GE(ckpt_step + 2, int64_t(logged)) << "more than one checkpoint interval lost";
    // Resume in one process (another world size) and finish.
    auto resume = args;
    resume[8] = std::to_string(ckpt_step + 4);   // --steps: a few more
    resume.erase(resume.end() - 2, resume.end());   // without --dist-timeout
    resume.push_back("--resume");
    const std::string err = dir.path("err.txt");
    ASSERT_EQ(wait_for(spawn_ltm(resume, {}, err), 300), 0) << read_file(err);
    EXPECT_EQ(read_checkpoint_state(dir.path("run/last.ltmckpt")).step, ckpt_step + 4);
    EXPECT_EQ(logged_losses(dir.path("run/log.jsonl")).size(), size_t(ckpt_step + 4));   // each step logged once
}
