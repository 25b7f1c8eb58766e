// libFuzzer target for the SCS status parser (see fuzz_mavlink_parser.cpp).
#include <cstddef>
#include <cstdint>

#include "hardware/scs/scs_protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  aerograsp::scs::PacketParser parser;
  for (std::size_t i = 0; i < size; ++i) parser.Push(data[i]);
  return 0;
}
