// libFuzzer target for the MAVLink parser and message readers. Built and run by
// scripts/run_fuzz.sh; longer, e.g.
//   build-fuzz/fuzz_mavlink_parser -max_total_time=600 tests/fuzz/corpus/mavlink
#include <cstddef>
#include <cstdint>

#include "hardware/mavlink/mavlink_codec.h"
#include "hardware/mavlink/mavlink_messages.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace aerograsp::mavlink;
  Parser parser;
  Parser strict;
  strict.RequireSigning(std::array<std::uint8_t, 32>{});
  for (std::size_t i = 0; i < size; ++i) {
    for (Parser* p : {&parser, &strict}) {
      if (p->Push(data[i]) != Parser::Result::kFrame) continue;
      const Frame& frame = p->frame();
      (void)Unpack<Heartbeat>(frame);
      (void)Unpack<SysStatus>(frame);
      (void)Unpack<CommandLong>(frame);
      (void)Unpack<CommandAck>(frame);
      (void)Unpack<SetPositionTargetLocalNed>(frame);
      (void)Unpack<StatusText>(frame).Text();
    }
  }
  return 0;
}
