// test_util.h: per-test temporary directories (each test writes only under its own).
#pragma once

#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

namespace ltm::test {

/// A fresh empty directory named after the running test, removed on destruction.
class TempDir {
public:
    TempDir() {
        const auto *info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_path = std::filesystem::temp_directory_path() /
                 ("ltm_test_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
                  std::to_string(::getpid()));
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    ~TempDir() { std::filesystem::remove_all(m_path); }
    std::string path(const std::string &name = "") const { return (m_path / name).string(); }
    /// Number of entries directly inside the directory.
    size_t count() const {
        size_t n = 0;
        for ([[maybe_unused]] const auto &e : std::filesystem::directory_iterator(m_path)) ++n;
        return n;
    }

private:
    std::filesystem::path m_path;
};

inline std::string source_path(const std::string &rel) { return std::string(LTM_SOURCE_DIR) + "/" + rel; }

}  // namespace ltm::test
