#pragma once
// CAIRN_CHECK: an always-on check of an invariant the code relies on (an index that must exist, a
// state a caller must have set up). A broken invariant is a bug, not bad input: it prints the
// condition, the file and line and the message to stderr and aborts, in every build type (unlike
// assert, which NDEBUG removes). Errors of input are never checked this way: loaders throw
// InputError (common/errors.h), cores return a reason, dds/ drops and counts bad samples.
#include <string>

namespace cairn {

[[noreturn]] void check_failed(const char* file, int line, const char* condition, const std::string& message);

}  // namespace cairn

/// CAIRN_CHECK(condition, message): message is any expression convertible to std::string, only
/// evaluated when the check fails.
#define CAIRN_CHECK(condition, message)                                               \
  do {                                                                                \
    if (!(condition)) ::cairn::check_failed(__FILE__, __LINE__, #condition, message); \
  } while (false)
