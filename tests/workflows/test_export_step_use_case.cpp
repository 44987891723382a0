// The export-step use case (export_step_command.hpp): the file written holds the patches read
// (read back through read_cad), the format follows write_cad's choice by extension whatever its
// case, the report states what was written, and an unknown extension writes nothing.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include "isospring/geometry/measure.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/export_step_command.hpp"

namespace isospring::workflows {
using namespace isospring::io;  // the formats the use cases read and write
namespace {
namespace fs = std::filesystem;

TEST(ExportStepUseCase, WritesTheBlockAsOneClosedSolidAndReportsIt) {
  const fs::path dir = fs::temp_directory_path() /
                       ("isospring_test_export_step_use_case-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  ExportStepCommandOptions options;
  options.input = std::string(ISOSPRING_SOURCE_DIR) + "/examples/cad/block.step";
  options.output = (dir / "block.step").string();
  const ExportStepCommandResult r = run_export_step(options);
  ASSERT_EQ(r.patches.size(), 1u);  // the hexahedral block: one volume patch
  EXPECT_EQ(r.format, "step");
  EXPECT_EQ(r.written.solids, 1);
  EXPECT_EQ(r.written.faces, 6);
  EXPECT_TRUE(r.written.notes.empty());
  EXPECT_EQ(r.file_bytes, fs::file_size(options.output));
  const geometry::CadModel back = geometry::read_cad(options.output);
  EXPECT_EQ(back.solids, 1);
  EXPECT_EQ(back.face_patches.size(), 6u);
  EXPECT_NEAR(geometry::measure(back.face_patches) / 0.0088, 1.0, 1e-12);

  nlohmann::json json;
  MarkdownReport md;
  export_step_report(r, options, json, md);
  EXPECT_EQ(json["format"], "step");
  EXPECT_EQ(json["patches"], 1);
  EXPECT_EQ(json["faces"], 6);
  EXPECT_EQ(json["solids"], 1);
  EXPECT_EQ(json["file_bytes"], r.file_bytes);
  EXPECT_EQ(json["units"], "m");
  EXPECT_EQ(export_step_summary(r, options),
            "wrote " + options.output + ": 1 patches (1 solid(s))");

  // write_cad lower-cases the extension, so .IGS is IGES, and the report says so.
  options.output = (dir / "block.IGS").string();
  const ExportStepCommandResult iges = run_export_step(options);
  EXPECT_EQ(iges.format, "iges");
  EXPECT_EQ(geometry::read_cad(options.output).face_patches.size(), 6u);

  options.output = (dir / "block.obj").string();
  EXPECT_THROW(run_export_step(options), nurbs::InputError);
  EXPECT_FALSE(fs::exists(options.output));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace isospring::workflows
