// file_util.h: whole-file reads with one-line errors, and atomic writes (tmp + rename), so a
// failed or interrupted command never leaves a half-written output behind.
#pragma once

#include <cstddef>
#include <fstream>
#include <string>
#include <string_view>

namespace ltm {

/// Reads a whole file; throws "path: cannot read: <reason>".
std::string read_file(const std::string &path);

/// A whole file mapped read-only (mmap): its bytes without a copy, for as long as the object lives
/// (weights and dataset records are parsed straight from the page cache). Throws as read_file.
class MappedFile {
public:
    explicit MappedFile(const std::string &path);
    ~MappedFile();
    MappedFile(const MappedFile &) = delete;
    MappedFile &operator=(const MappedFile &) = delete;
    std::string_view bytes() const { return m_data ? std::string_view(static_cast<const char *>(m_data), m_size) : std::string_view(m_owned); }

private:
    void *m_data = nullptr;   // the mapping, and its length
    size_t m_size = 0;
    std::string m_owned;   // what a pipe, a /proc file or an empty file held: those are not mapped
};

/// Writes to "<path>.tmp.<pid>" and renames onto `path` on commit(); removes the temporary
/// file if destroyed without commit (an exception unwound through the writer).
class AtomicFile {
public:
    explicit AtomicFile(std::string path, bool binary = true);
    ~AtomicFile();
    AtomicFile(const AtomicFile &) = delete;
    AtomicFile &operator=(const AtomicFile &) = delete;
    std::ostream &stream() { return m_out; }
    std::ofstream &file() { return m_out; }
    const std::string &tmp_path() const { return m_tmp; }
    /// Flushes, checks for write errors, renames into place.
    void commit();

private:
    std::string m_path, m_tmp;
    std::ofstream m_out;
    bool m_committed = false;
};

/// Throws "path: cannot write: directory 'dir' does not exist" unless the file's directory exists:
/// what AtomicFile checks, for a command to call before its work rather than after it.
void check_output_directory(const std::string &path);

/// Writes a string atomically.
void write_file_atomic(const std::string &path, const std::string &contents);

/// Creates a directory and its parents; throws with the path if impossible.
void create_directories(const std::string &dir);

/// Lower-case extension without the dot ("json" for "a/b.scene.json").
std::string file_extension(const std::string &path);
/// Directory part of a path ("" for a bare file name).
std::string parent_dir(const std::string &path);

}  // namespace ltm
