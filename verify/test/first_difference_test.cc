// FirstDifference names the row, frame or byte where two outputs part, counted by hand.
#include "verify/first_difference.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <string>

namespace sitlnet::verify {
namespace {

TEST(FirstDifferenceTest, NamesTheCsvRowAndItsTime) {
  const std::string a = "time_ns,from,to\n100,0,1\n200,1,0\n300,0,1\n";
  const std::string b = "time_ns,from,to\n100,0,1\n200,1,0\n300,0,2\n";
  const std::string where = FirstDifference("deliveries.csv", a, b);
  EXPECT_EQ(where.rfind("first at row 3 (time_ns 300): \"300,0,1\" vs \"300,0,2\"", 0), 0u)
      << where;
}

TEST(FirstDifferenceTest, NamesTheLineOfALog) {
  const std::string where = FirstDifference("robots/a.log", "up\nstate 1\n", "up\nstate 2\n");
  EXPECT_EQ(where.rfind("first at line 2", 0), 0u) << where;
}

TEST(FirstDifferenceTest, NamesThePcapFrameAndItsTime) {
  // Two records of 4 bytes each after the 24-byte header; the second differs at its third byte.
  const auto record = [](uint32_t sec, uint32_t usec, const std::string& data) {
    std::string r;
    for (uint32_t v : {sec, usec, 4u, 4u}) {
      for (int i = 0; i < 4; ++i) r.push_back(static_cast<char>(v >> (8 * i)));
    }
    return r + data;
  };
  const std::string header(24, '\0');
  const std::string a = header + record(0, 10, "abcd") + record(2, 500, "efgh");
  const std::string b = header + record(0, 10, "abcd") + record(2, 500, "efXh");
  EXPECT_EQ(FirstDifference("medium.pcap", a, b),
            "first at frame 2 (2.000500 s), byte 2 of its record");
}

TEST(FirstDifferenceTest, DecompressesAGzipCsv) {
  const auto gzip = [](const std::string& text) {
    z_stream stream{};
    deflateInit2(&stream, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
    std::string out(compressBound(text.size()) + 64, '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
    stream.avail_in = text.size();
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = out.size();
    deflate(&stream, Z_FINISH);
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return out;
  };
  const std::string where = FirstDifference("losses.csv.gz", gzip("time_ns,cause\n5,decoded\n"),
                                            gzip("time_ns,cause\n5,collision\n"));
  EXPECT_EQ(where.rfind("decompressed, first at row 1 (time_ns 5)", 0), 0u) << where;
}

TEST(FirstDifferenceTest, NamesTheByteOfAnythingElse) {
  EXPECT_EQ(FirstDifference("trajectories.png", "\x89PNGab", "\x89PNGac"),
            "first at byte 5 (of 6 and 6)");
}

}  // namespace
}  // namespace sitlnet::verify
