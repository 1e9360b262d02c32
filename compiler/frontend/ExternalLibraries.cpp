// Compiles external C code with the system compiler and loads it
// (ExternalLibraries.h). An entry of the cache is `ext-<sha256>.so`; the
// key covers the generated source, every source file's contents, the flags
// and the compiler's identity (its resolved path, size and modification
// time), so a changed library or compiler builds again.
#include "frontend/ExternalLibraries.h"

#include <openssl/evp.h>

#include <dlfcn.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

extern char **environ;

namespace ldae::frontend {
namespace {

namespace fs = std::filesystem;

const char *const kFlags[] = {"-shared", "-fPIC", "-O2", "-w"};

std::optional<std::string> readFile(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Everything the shared object depends on, in one string to hash; an
/// error when a source cannot be read.
Expected<std::string> keyText(const CBuild &b) {
  std::string text = "ldaec external C v1\n";
  std::error_code ec;
  fs::path cc = fs::canonical(kCCompiler, ec);
  struct stat st {};
  if (ec || stat(cc.c_str(), &st) != 0)
    return Error{std::string("the C compiler ") + kCCompiler +
                 " was not found"};
  text += cc.string() + " " + std::to_string(st.st_size) + " " +
          std::to_string(st.st_mtim.tv_sec) + "\n";
  for (const char *f : kFlags)
    text += std::string(f) + "\n";
  for (const std::string &d : b.includeDirs)
    text += "-I" + d + "\n";
  for (const std::string &l : b.libraries)
    text += "-l" + l + "\n";
  for (const std::string &d : b.defines)
    text += "-D" + d + "\n";
  text += std::to_string(b.source.size()) + "\n" + b.source;
  for (const std::string &f : b.files) {
    std::optional<std::string> contents = readFile(f);
    if (!contents)
      return Error{"cannot read '" + f + "'"};
    text += f + "\n" + std::to_string(contents->size()) + "\n" + *contents;
  }
  // Headers are not listed: include directories are hashed by the contents
  // of their .h files, which the sources may read.
  for (const std::string &d : b.includeDirs) {
    std::map<std::string, std::string> headers;
    for (const auto &e : fs::directory_iterator(d, ec))
      if (e.path().extension() == ".h")
        if (auto h = readFile(e.path().string()))
          headers[e.path().filename().string()] = *h;
    for (const auto &[name, contents] : headers)
      text += name + "\n" + std::to_string(contents.size()) + "\n" + contents;
  }
  return text;
}

/// Whether `dir` is this user's alone (the object cache's rule): owned by
/// the user, not a symbolic link, writable by no one else.
bool trustedDir(const std::string &dir) {
  struct stat st {};
  return lstat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode) &&
         st.st_uid == geteuid() && (st.st_mode & (S_IWGRP | S_IWOTH)) == 0;
}

/// Whether entry `path` may be loaded: a regular file of this user's that
/// no one else can write.
bool trustedEntry(const std::string &path) {
  struct stat st {};
  return lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
         st.st_uid == geteuid() && (st.st_mode & (S_IWGRP | S_IWOTH)) == 0;
}

/// A directory to build in: the cache when it is usable, else a private
/// temporary directory ("" when none can be made).
std::string buildDir(const std::string &cacheDir, bool &cached) {
  cached = false;
  if (!cacheDir.empty()) {
    std::error_code ec;
    fs::create_directories(cacheDir, ec);
    if (!ec)
      chmod(cacheDir.c_str(), 0700);
    if (trustedDir(cacheDir)) {
      cached = true;
      return cacheDir;
    }
  }
  static std::string temp = [] {
    std::string pattern =
        (fs::temp_directory_path() / "ldaec-ext-XXXXXX").string();
    return mkdtemp(pattern.data()) ? pattern : std::string();
  }();
  return temp;
}

/// Runs the compiler; "" on success, else its first messages.
std::string runCompiler(const std::vector<std::string> &args,
                        const std::string &logPath,
                        const std::string &sourcePath) {
  std::vector<char *> argv;
  for (const std::string &a : args)
    argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, logPath.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0)
    return std::string("cannot run the C compiler ") + kCCompiler;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
    return "";
  std::string log = readFile(logPath).value_or("");
  // The first error line says most; the generated file's name says nothing.
  std::istringstream lines(log);
  std::string line, first;
  while (first.empty() && std::getline(lines, line))
    if (line.find("error") != std::string::npos)
      first = line;
  if (size_t at = first.find(sourcePath); at != std::string::npos)
    first.replace(at, sourcePath.size(), "generated C");
  return first.empty() ? "the C compiler failed" : first;
}

} // namespace

Expected<LoadedC> loadCBuild(const CBuild &build, const std::string &cacheDir) {
  static std::mutex mutex; // one build of an entry at a time in a process
  std::lock_guard lock(mutex);
  // A build already loaded by this process (the same function called in
  // many places): its files are not read and hashed again.
  static std::map<std::string, LoadedC> loaded;
  std::string request = build.source + '\0' + cacheDir;
  for (const auto *list : {&build.files, &build.includeDirs, &build.libraries,
                           &build.defines})
    for (const std::string &item : *list)
      request += '\0' + item;
  if (auto it = loaded.find(request); it != loaded.end())
    return it->second;
  auto text = keyText(build);
  if (!text)
    return Error{text.error()};
  bool cached = false;
  std::string dir = buildDir(cacheDir, cached);
  if (dir.empty())
    return Error{"no directory to build external C code in"};
  std::string key = sha256Hex(*text);
  std::string entry = dir + "/ext-" + key + ".so";
  if (!cached || !trustedEntry(entry)) {
    std::string stem = dir + "/ext-" + key + ".tmp" + std::to_string(getpid());
    std::string source = stem + ".c", object = stem + ".so", log = stem + ".log";
    {
      std::ofstream out(source, std::ios::binary);
      out << build.source;
      if (!out)
        return Error{"cannot write '" + source + "'"};
    }
    std::vector<std::string> args{kCCompiler};
    for (const char *f : kFlags)
      args.push_back(f);
    for (const std::string &d : build.includeDirs)
      args.push_back("-I" + d);
    for (const std::string &d : build.defines)
      args.push_back("-D" + d);
    args.push_back("-o");
    args.push_back(object);
    args.push_back(source);
    for (const std::string &f : build.files)
      args.push_back(f);
    for (const std::string &l : build.libraries)
      args.push_back("-l" + l);
    std::string failure = runCompiler(args, log, source);
    std::error_code ec;
    fs::remove(source, ec);
    fs::remove(log, ec);
    if (!failure.empty()) {
      fs::remove(object, ec);
      return Error{failure};
    }
    chmod(object.c_str(), 0600);
    fs::rename(object, entry, ec);
    if (ec)
      return Error{"cannot store '" + entry + "': " + ec.message()};
  }
  void *handle = dlopen(entry.c_str(), RTLD_NOW | RTLD_GLOBAL);
  if (!handle)
    return Error{std::string("cannot load the compiled C code: ") + dlerror()};
  LoadedC result{handle, entry};
  loaded.emplace(std::move(request), result);
  return result;
}


std::string sha256Hex(const std::string &data) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  EVP_Digest(data.data(), data.size(), digest, &len, EVP_sha256(), nullptr);
  static const char hex[] = "0123456789abcdef";
  std::string out;
  for (unsigned i = 0; i < len; ++i) {
    out += hex[digest[i] >> 4];
    out += hex[digest[i] & 15];
  }
  return out;
}

} // namespace ldae::frontend
