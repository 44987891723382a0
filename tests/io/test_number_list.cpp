// Comma-separated numbers of command-line options (io/number_list.hpp).
#include <gtest/gtest.h>

#include "isospring/io/number_list.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

TEST(NumberList, ReadsFiniteNumbers) {
  EXPECT_EQ(parse_number_list("0.3,0.5", "--at"), (std::vector<double>{0.3, 0.5}));
  EXPECT_EQ(parse_number_list("-1e-3", "--at"), (std::vector<double>{-1e-3}));
}

TEST(NumberList, AnythingElseNamesTheOption) {
  for (const char* bad : {"", "0.3,x", "1,,2", "inf", "0.5 "}) {
    try {
      parse_number_list(bad, "--gravity");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const nurbs::InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--gravity: ", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace isospring::io
