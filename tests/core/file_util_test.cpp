// file_util_test.cpp: atomic writes leave either the whole file or nothing.
#include <filesystem>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "test_util.h"

using namespace ltm;

TEST(AtomicFile, UncommittedWriteLeavesNothing) {
    test::TempDir dir;
    {
        AtomicFile f(dir.path("out.bin"));
        f.stream() << "partial";
    }
    EXPECT_EQ(dir.count(), 0u);
}

TEST(AtomicFile, CommitPublishesTheWholeFile) {
    test::TempDir dir;
    write_file_atomic(dir.path("out.txt"), "hello");
    EXPECT_EQ(read_file(dir.path("out.txt")), "hello");
    EXPECT_EQ(dir.count(), 1u);
}

TEST(AtomicFile, MissingDirectoryIsAnError) {
    test::TempDir dir;
    EXPECT_THROW(AtomicFile(dir.path("nope/out.txt")), Error);
    EXPECT_THROW(read_file(dir.path("missing.txt")), Error);
}
