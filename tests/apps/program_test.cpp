// program_test.cpp: the `ltm` program as a user runs it (apps/ltm/delegate.h). In a libtorch build
// `ltm` does not load libtorch: it renders weights at their prior itself and hands what needs a
// network to `ltm-torch` beside it (exec: the same arguments, output and exit code). Without
// libtorch the same commands say in one line that libtorch is needed.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "ltm/core/file_util.h"
#include "active_weights.h"
#include "test_util.h"

namespace ltm {
namespace {

struct Ran {
    int code;
    std::string out;   // stdout and stderr
};
Ran run_program(const std::string &args) {
    std::string out;
    FILE *p = ::popen((std::string(LTM_PROGRAM_DIR) + "/ltm " + args + " 2>&1").c_str(), "r");
    if (!p) return {-1, ""};
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

bool with_libtorch() { return std::ifstream(std::string(LTM_PROGRAM_DIR) + "/ltm-torch").good(); }

}  // namespace

TEST(Program, LtmLoadsNoLibtorchAndHandsOverWhatNeedsIt) {
    // The program's own dynamic dependencies: libtorch's would name its libraries.
    const std::string bytes = read_file(std::string(LTM_PROGRAM_DIR) + "/ltm");
    for (const char *lib : {"libtorch_cpu.so", "libc10.so"}) EXPECT_EQ(bytes.find(lib), std::string::npos) << lib;
    Ran r = run_program("--help");
    EXPECT_EQ(r.code, 0) << r.out;
    for (const char *cmd : {"render", "bake-gi", "train", "export", "eval"}) EXPECT_NE(r.out.find(cmd), std::string::npos) << cmd;
    test::TempDir dir;
    const std::string render = "render builtin:cornell-box --method neural --scene-points 2048 --width 12 --height 12 --quiet --model ";
    r = run_program(render + test::source_path("models/ltm-cpu.safetensors") + " -o " + dir.path("prior"));
    EXPECT_EQ(r.code, 0) << r.out;
    // The shipped model's body is silent and its skip 1: it folds to its regather alone, without libtorch.
    EXPECT_NE(read_file(dir.path("prior.timings.json")).find("\"network\": \"folded at w = 1: the regather alone"), std::string::npos);
    EXPECT_NE(read_file(dir.path("prior.timings.json")).find("without libtorch"), std::string::npos);
    const std::string active = dir.path("active.safetensors");
    test::write_active_weights(test::source_path("models/ltm-cpu.safetensors"), active);
    r = run_program("train --help");
    const Ran a = run_program(render + active + " -o " + dir.path("active"));
    if (with_libtorch()) {
        EXPECT_EQ(r.code, 0) << r.out;
        EXPECT_NE(r.out.find("--steps"), std::string::npos) << "train's own help, from ltm-torch: " << r.out;
        EXPECT_EQ(a.code, 0) << a.out;
        EXPECT_NE(read_file(dir.path("active.timings.json")).find("\"network\": \"active\""), std::string::npos);
    } else {
        EXPECT_EQ(r.code, 1) << r.out;
        EXPECT_NE(r.out.find("ltm train: error: the command needs libtorch"), std::string::npos) << r.out;
        EXPECT_EQ(a.code, 1) << a.out;
        EXPECT_NE(a.out.find("ltm render: error: "), std::string::npos) << a.out;
        EXPECT_NE(a.out.find("needs libtorch"), std::string::npos) << a.out;
        EXPECT_FALSE(std::ifstream(dir.path("active.exr")).good()) << "nothing written";
    }
}

}  // namespace ltm
