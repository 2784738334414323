// What the console's HTTP endpoints parse from a request body (base_station/console): the first
// byte picks the parser, the rest is the body. Every bad body must give an error naming the
// fault (the server answers 400 with it), never crash the base.
#include "base_station/console/command_api.h"
#include "base_station/console/search_api.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  using namespace cairn;
  const std::string body(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::string error;
  switch (data[0] % 5) {
    case 0:
      (void)base::parse_command_request(body, {RobotId(0), RobotId(1), RobotId(3)}, &error);
      break;
    case 1:
      (void)base::parse_verdict_request(ObjectId{RobotId(1), 2}, body, &error);
      break;
    case 2:
      (void)base::parse_search_request(body, &error);
      break;
    case 3:
      (void)base::parse_alignment_request(RobotId(1), body, &error);
      break;
    case 4:  // the journal's alignment record
      (void)base::alignment_request_from_json(body, &error);
      break;
  }
  return 0;
}
