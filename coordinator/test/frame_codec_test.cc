#include "coordinator/frame_codec.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "common/common.h"

namespace sitlnet::coordinator {
namespace {

using proto::coord::CoordinatorMessage;

CoordinatorMessage EndWithRobots(int robots, bool noisy) {
  CoordinatorMessage message;
  proto::coord::End* end = message.mutable_end();
  end->set_iteration(42);
  end->set_busy_ns(123456);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(-100, 100);
  for (int i = 0; i < 3 * robots; ++i) {
    end->mutable_poses()->add_position_m(noisy ? uniform(random) : 1.0 * (i % 4));
  }
  return message;
}

// Decodes what Encode produced, through the public header/body functions.
CoordinatorMessage RoundTrip(std::string_view frame, size_t max = kDefaultMaxFrameBytes) {
  FrameEncoding encoding{};
  const size_t body =
      ParseFrameHeader(reinterpret_cast<const uint8_t*>(frame.data()), max, &encoding);
  EXPECT_EQ(body + kFrameHeaderBytes, frame.size());
  FrameScratch scratch;
  CoordinatorMessage decoded;
  DecodeFrameBody(encoding, frame.substr(kFrameHeaderBytes), max, &scratch, &decoded);
  return decoded;
}

TEST(FrameCodec, RawRoundTripIsExact) {
  const CoordinatorMessage message = EndWithRobots(64, /*noisy=*/true);
  FrameEncoder encoder;
  const std::string frame(encoder.Encode(message));
  EXPECT_EQ(encoder.last_encoding(), FrameEncoding::kProtobuf);
  EXPECT_EQ(frame.size(), kFrameHeaderBytes + message.ByteSizeLong());
  EXPECT_EQ(RoundTrip(frame).SerializeAsString(), message.SerializeAsString());
}

TEST(FrameCodec, CompressesOnlyAboveThreshold) {
  const CoordinatorMessage message = EndWithRobots(100, /*noisy=*/false);
  const size_t size = message.ByteSizeLong();
  FrameCodecOptions at;
  at.compress_above_bytes = size;  // "strictly larger": not compressed.
  FrameEncoder encoder_at(at);
  encoder_at.Encode(message);
  EXPECT_EQ(encoder_at.last_encoding(), FrameEncoding::kProtobuf);

  FrameCodecOptions below;
  below.compress_above_bytes = size - 1;
  FrameEncoder encoder(below);
  const std::string frame(encoder.Encode(message));
  EXPECT_EQ(encoder.last_encoding(), FrameEncoding::kZlib);
  EXPECT_LT(frame.size(), size);  // A repeating pattern shrinks.
  EXPECT_EQ(RoundTrip(frame).SerializeAsString(), message.SerializeAsString());
}

TEST(FrameCodec, IncompressibleBodyGoesOutRaw) {
  CoordinatorMessage message;
  std::string noise(4096, '\0');
  std::mt19937 random(3);
  for (char& c : noise) c = static_cast<char>(random());
  message.mutable_end()->set_payload(noise);
  FrameCodecOptions options;
  options.compress_above_bytes = 0;
  FrameEncoder encoder(options);
  const std::string frame(encoder.Encode(message));
  EXPECT_EQ(encoder.last_encoding(), FrameEncoding::kProtobuf);
  EXPECT_EQ(RoundTrip(frame).end().payload(), noise);
}

TEST(FrameCodec, RejectsTooLongBody) {
  uint8_t header[8] = {0x01, 0x00, 0x00, 0x10, 0, 0, 0, 0};  // 256 MiB + 1
  FrameEncoding encoding{};
  try {
    ParseFrameHeader(header, kDefaultMaxFrameBytes, &encoding);
    FAIL() << "accepted a 256 MiB frame";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "bad frame: body of 268435457 bytes exceeds the limit of 67108864 bytes");
  }
}

TEST(FrameCodec, RejectsUnknownEncodingAndReservedBytes) {
  FrameEncoding encoding{};
  uint8_t unknown[8] = {4, 0, 0, 0, 7, 0, 0, 0};
  EXPECT_THROW(ParseFrameHeader(unknown, 100, &encoding), Error);
  uint8_t reserved[8] = {4, 0, 0, 0, 0, 0, 1, 0};
  EXPECT_THROW(ParseFrameHeader(reserved, 100, &encoding), Error);
}

TEST(FrameCodec, RejectsCorruptZlibAndWrongDeclaredLength) {
  const CoordinatorMessage message = EndWithRobots(100, false);
  FrameCodecOptions options;
  options.compress_above_bytes = 0;
  FrameEncoder encoder(options);
  std::string frame(encoder.Encode(message));
  ASSERT_EQ(encoder.last_encoding(), FrameEncoding::kZlib);
  FrameScratch scratch;
  CoordinatorMessage decoded;

  std::string corrupt = frame.substr(kFrameHeaderBytes);
  corrupt[corrupt.size() / 2] ^= 0x5a;
  corrupt[corrupt.size() / 2 + 1] ^= 0xa5;
  EXPECT_THROW(
      DecodeFrameBody(FrameEncoding::kZlib, corrupt, kDefaultMaxFrameBytes, &scratch, &decoded),
      Error);

  std::string lying = frame.substr(kFrameHeaderBytes);
  lying[0] = static_cast<char>(lying[0] + 1);  // Declares one byte more than inflates.
  try {
    DecodeFrameBody(FrameEncoding::kZlib, lying, kDefaultMaxFrameBytes, &scratch, &decoded);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("header declared"), std::string::npos) << e.what();
  }
  // A declared length above the limit is refused before inflating.
  EXPECT_THROW(DecodeFrameBody(FrameEncoding::kZlib, frame.substr(kFrameHeaderBytes), 10, &scratch,
                               &decoded),
               Error);
}

TEST(FrameCodec, RejectsBytesThatAreNotAMessage) {
  FrameScratch scratch;
  CoordinatorMessage decoded;
  // Field 1 (hello), wire type 2, length 100, but only 2 bytes follow.
  const std::string garbage("\x0a\x64\x01\x02", 4);
  try {
    DecodeFrameBody(FrameEncoding::kProtobuf, garbage, 1000, &scratch, &decoded);
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "bad frame: 4 bytes are not a valid CoordinatorMessage");
  }
}

}  // namespace
}  // namespace sitlnet::coordinator
