// file_util.cpp: std::filesystem with errors turned into ltm::Error naming the path.
#include "ltm/core/file_util.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sstream>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "ltm/core/error.h"

namespace fs = std::filesystem;

namespace ltm {

namespace {
// Pipes, devices and /proc files (regular, but of size 0) have no size to map: read them as a stream.
std::string read_stream(const std::string &path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) LTM_THROW(path, ": cannot read: ", std::strerror(errno));
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) LTM_THROW(path, ": read error");
    return ss.str();
}
}  // namespace

std::string read_file(const std::string &path) {
    const MappedFile f(path);
    return std::string(f.bytes());
}

MappedFile::MappedFile(const std::string &path) {
    if (fs::is_directory(path)) LTM_THROW(path, ": is a directory, expected a file");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) LTM_THROW(path, ": cannot read: ", std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int err = errno;
        ::close(fd);
        LTM_THROW(path, ": cannot read: ", std::strerror(err));
    }
    if (!S_ISREG(st.st_mode) || st.st_size == 0) {   // /proc files are regular with size 0
        ::close(fd);
        m_owned = read_stream(path);
        return;
    }
    m_size = size_t(st.st_size);
    m_data = ::mmap(nullptr, m_size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (m_data == MAP_FAILED) {
        const int err = errno;
        m_data = nullptr;
        ::close(fd);
        LTM_THROW(path, ": cannot read: ", std::strerror(err));
    }
    ::close(fd);   // the mapping keeps the file
}

MappedFile::~MappedFile() {
    if (m_data) ::munmap(m_data, m_size);
}

AtomicFile::AtomicFile(std::string path, bool binary) : m_path(std::move(path)) {
    m_tmp = m_path + ".tmp." + std::to_string(::getpid());
    check_output_directory(m_path);
    m_out.open(m_tmp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
    if (!m_out) LTM_THROW(m_path, ": cannot write: ", std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (!m_committed) {
        m_out.close();
        std::error_code ec;
        fs::remove(m_tmp, ec);
    }
}

void AtomicFile::commit() {
    m_out.flush();
    if (!m_out) LTM_THROW(m_path, ": write failed (disk full?)");
    m_out.close();
    std::error_code ec;
    fs::rename(m_tmp, m_path, ec);
    if (ec) LTM_THROW(m_path, ": cannot rename into place: ", ec.message());
    m_committed = true;
}

void check_output_directory(const std::string &path) {
    const std::string dir = parent_dir(path);
    if (!dir.empty() && !fs::is_directory(dir)) LTM_THROW(path, ": cannot write: directory '", dir, "' does not exist");
}

void write_file_atomic(const std::string &path, const std::string &contents) {
    AtomicFile f(path);
    f.stream().write(contents.data(), std::streamsize(contents.size()));
    f.commit();
}

void create_directories(const std::string &dir) {
    if (dir.empty()) return;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) LTM_THROW(dir, ": cannot create directory: ", ec.message());
}

std::string file_extension(const std::string &path) {
    std::string ext = fs::path(path).extension().string();
    if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
    for (char &c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

std::string parent_dir(const std::string &path) { return fs::path(path).parent_path().string(); }

}  // namespace ltm
