#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <mutex>
#include <stdexcept>
#include <string>

#include "dynamap/localization/icp_module.h"

namespace dynamap {
namespace {

using AlignFn = int (*)(const mrpt::maps::CSimplePointsMap*, const mrpt::maps::CSimplePointsMap*,
                        const mrpt::poses::CPose2D*, const IcpParams*, mrpt::poses::CPose2D*,
                        unsigned*, std::string*);

constexpr const char* kModule = "libdynamap_icp.so";

// The directory of the running executable ("" if unknown), where the build puts the module.
std::string executableDir() {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return "";
  const std::string path(buf, static_cast<std::size_t>(n));
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// The directory of the shared object holding this code ("" if it is the executable): the
// Python module, run by an interpreter that lives elsewhere, has the module built beside it.
std::string libraryDir() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&executableDir), &info) == 0 || info.dli_fname == nullptr)
    return "";
  const std::string path = info.dli_fname;
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// Beside the executable first, then (installed) ../lib/dynamap/, then beside the shared object
// holding this code, then the loader's own search.
AlignFn loadAlign() {
  const std::string dir = executableDir();
  std::string errors;
  for (const std::string& candidate : {dir + kModule, dir + "../lib/dynamap/" + kModule,
                                       libraryDir() + kModule, std::string(kModule)}) {
    void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* e = ::dlerror();
      errors += std::string("\n  ") + (e != nullptr ? e : candidate.c_str());
      continue;
    }
    if (void* fn = ::dlsym(handle, "dynamap_icp_align")) return reinterpret_cast<AlignFn>(fn);
    errors += "\n  " + candidate + ": no dynamap_icp_align";
    ::dlclose(handle);
  }
  throw std::runtime_error(std::string("scan matching needs ") + kModule +
                           " (built beside the dynamap executable), which did not load:" + errors);
}

// The module's entry point, loaded once per process; a failure is remembered and thrown again
// at every call.
AlignFn alignFunction() {
  static std::once_flag once;
  static AlignFn align = nullptr;
  static std::string load_error;
  std::call_once(once, [] {
    try {
      align = loadAlign();
    } catch (const std::exception& e) {
      load_error = e.what();
    }
  });
  if (align == nullptr) throw std::runtime_error(load_error);
  return align;
}

}  // namespace

void requireIcpModule() {
  alignFunction();
}

mrpt::poses::CPose2D icpAlignModule(const mrpt::maps::CSimplePointsMap& reference,
                                    const mrpt::maps::CSimplePointsMap& scan,
                                    const mrpt::poses::CPose2D& start, const IcpParams& params,
                                    unsigned& iterations) {
  const AlignFn align = alignFunction();
  mrpt::poses::CPose2D out;
  std::string error;
  if (align(&reference, &scan, &start, &params, &out, &iterations, &error) == 0) {
    throw std::runtime_error("ICP failed: " + error);
  }
  return out;
}

}  // namespace dynamap
