#include "sensor/image_io.h"

#include <dlfcn.h>

#include <cstdlib>
#include <map>
#include <mutex>
#include <system_error>

namespace vts {
namespace {

using ReadFn = int (*)(const char*, GreyImage*, std::string*);
using AbiFn = int (*)();

// The module at `file`, or nullptr with why it cannot be used in `why`.
// Loaded modules stay loaded (the dynamic loader keeps one copy per file).
ReadFn open_module(const std::string& file, std::string& why) {
  static std::mutex mutex;
  static std::map<std::string, ReadFn> loaded;
  const std::lock_guard lock(mutex);
  if (const auto it = loaded.find(file); it != loaded.end()) return it->second;
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* e = dlerror();
    why = e ? e : "cannot be loaded";
    return nullptr;
  }
  const auto abi = reinterpret_cast<AbiFn>(dlsym(handle, "vts_image_module_abi"));
  const auto read = reinterpret_cast<ReadFn>(dlsym(handle, "vts_image_module_read"));
  if (!abi || !read) {
    why = file + " is no vts image module (no vts_image_module_read)";
    dlclose(handle);
    return nullptr;
  }
  if (abi() != kImageModuleAbi) {
    why = file + " is a vts image module of interface " + std::to_string(abi()) + ", this program needs " +
          std::to_string(kImageModuleAbi) + " (a module left from another build?)";
    dlclose(handle);
    return nullptr;
  }
  loaded.emplace(file, read);
  return read;
}

ReadFn find_module(std::string& tried) {
  std::vector<std::string> files;
  if (const char* env = std::getenv("VTS_IMAGE_MODULE"); env && *env) {
    files.emplace_back(env);
  } else {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      files.push_back((exe.parent_path() / kImageModuleFile).string());
      files.push_back((exe.parent_path() / ".." / "lib" / "vts" / kImageModuleFile).lexically_normal().string());
    }
    files.emplace_back(kImageModuleFile);  // the library search path
  }
  for (const std::string& file : files) {
    std::string why;
    if (const ReadFn read = open_module(file, why)) return read;
    tried += (tried.empty() ? "" : "; ") + why;
  }
  return nullptr;
}

}  // namespace

GreyImage read_grey_image(const std::filesystem::path& path) {
  std::string tried;
  const ReadFn read = find_module(tried);
  if (!read)
    throw ImageError(path.string() + ": reading images needs vts's OpenImageIO module " + kImageModuleFile +
                     ", which could not be loaded (set VTS_IMAGE_MODULE to its file): " + tried);
  GreyImage img;
  std::string error;
  if (!read(path.c_str(), &img, &error)) throw ImageError(error);
  return img;
}

}  // namespace vts
