// `isospring export` end to end: every format from one model.json, read back (json exactly,
// VTK with VTK's reader, MJCF/SOFA by their element counts), and the exit codes for bad input.
#include <gtest/gtest.h>

#include <unistd.h>  // getpid: CTest runs tests in parallel processes
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>
#include "../analysis/beam_lattice.hpp"

#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include "isospring/io/model_file.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;

int run(const std::string& arguments) {
  const std::string command = std::string(ISOSPRING_EXECUTABLE) + " " + arguments + " 2>/dev/null";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

long count(const std::string& text, const std::string& pattern) {
  const std::regex r(pattern);
  return std::distance(std::sregex_iterator(text.begin(), text.end(), r), std::sregex_iterator());
}

class ExportCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(ISOSPRING_EXECUTABLE)) GTEST_SKIP() << "the isospring program is not built";
    dir_ = fs::temp_directory_path() /
           (std::string("isospring_test_export_command-") + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    network_.positions = {{0, 0, 0}, {0.1, 0, 0}, {0.1, 0.1, 0}, {0, 0.1, 0}};
    network_.masses = {0.1, 0.1, 0.2, 0.1};
    network_.fixed = {true, false, false, true};
    network_.springs = {{0, 1, 100, 1, 0.1, 0},
                        {1, 2, 200, 1, 0.1, 0},
                        {2, 3, 100, 1, 0.1, 0},
                        {0, 2, 50, 1, std::sqrt(0.02), 1},
                        {1, 3, 50, 1, std::sqrt(0.02), 1}};
    write_model_json(dir_ / "model.json", network_, {{"case", "square"}});
  }
  fs::path dir_;
  analysis::SpringNetwork network_;
};

TEST_F(ExportCommand, WritesEveryFormat) {
  const std::string model = (dir_ / "model.json").string();
  ASSERT_EQ(run("export " + model + " -q -o " + (dir_ / "copy.json").string()), 0);
  EXPECT_EQ(model_to_json(read_model_json(dir_ / "copy.json").network), model_to_json(network_));

  ASSERT_EQ(run("export " + model + " -q --format mjcf -o " + (dir_ / "m.xml").string()), 0);
  const std::string mjcf = read(dir_ / "m.xml");
  EXPECT_EQ(count(mjcf, "<body "), 2);
  EXPECT_EQ(count(mjcf, "<spatial "), 5);
  EXPECT_NE(mjcf.find("gravity=\"0 0 -9.8100000000000005\""), std::string::npos);

  ASSERT_EQ(run("export " + model + " -q --gravity 0,-1,0 -o " + (dir_ / "s.scn").string()), 0);
  const std::string scene = read(dir_ / "s.scn");
  EXPECT_NE(scene.find("<StiffSpringForceField"), std::string::npos);
  EXPECT_NE(scene.find("gravity=\"0 -1 0\""), std::string::npos);
  EXPECT_NE(scene.find("indices=\"0 3\""), std::string::npos);

  ASSERT_EQ(run("export " + model + " -q -o " + (dir_ / "springs.vtp").string()), 0);
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName((dir_ / "springs.vtp").c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfLines(), 5);

  ASSERT_EQ(run("export " + model + " -q -o " + (dir_ / "scene.vtm").string()), 0);
  EXPECT_TRUE(fs::exists(dir_ / "scene" / "springs.vtp"));

  // The reduced model: 3 modes of the 6 free DOFs (the model has no loads, so no load shapes).
  ASSERT_EQ(run("export " + model + " -q --format reduced --modes 3 -o " +
                (dir_ / "reduced.json").string()),
            0);
  const nlohmann::json reduced = nlohmann::json::parse(read(dir_ / "reduced.json"));
  EXPECT_EQ(reduced.at("format"), "isospring.reduced_spring_model");
  EXPECT_EQ(reduced.at("basis").size(), 12u);
  EXPECT_EQ(reduced.at("basis").at(0).size(), 3u);
  EXPECT_EQ(reduced.at("timestep"), 1e-3);
  const nlohmann::json report = nlohmann::json::parse(read(dir_ / "reduced.json.report.json"));
  EXPECT_EQ(report.at("basis_size"), 3);
  // --corotated (on a solid beam: its modal derivatives need a supported, non-flat network):
  // the corotation object, one neighbour list per particle.
  write_model_json(dir_ / "beam.json", analysis::beam_lattice(3, 2, 2, 1e3, 1e-3),
                   {{"case", "beam"}});
  ASSERT_EQ(
      run("export " + (dir_ / "beam.json").string() +
          " -q --format reduced --corotated --modes 4 -o " + (dir_ / "corotated.json").string()),
      0);
  const nlohmann::json corotated = nlohmann::json::parse(read(dir_ / "corotated.json"));
  EXPECT_EQ(corotated.at("corotation").at("neighbours").size(), 12u);
  EXPECT_FALSE(reduced.contains("corotation"));
}

TEST_F(ExportCommand, BadInputExitsWithStatusOne) {
  std::string text = read(dir_ / "model.json");
  text = std::regex_replace(text, std::regex("\"k\": 200"), "\"k\": -200",
                            std::regex_constants::format_first_only);
  std::ofstream(dir_ / "bad.json") << text;
  EXPECT_EQ(run("export " + (dir_ / "bad.json").string() + " -o " + (dir_ / "x.xml").string()), 1);
  EXPECT_FALSE(fs::exists(dir_ / "x.xml"));
  EXPECT_EQ(run("export " + (dir_ / "model.json").string() + " -o " + (dir_ / "x.abc").string()),
            1);
  EXPECT_EQ(run("export " + (dir_ / "model.json").string() + " --gravity 1,2 -o " +
                (dir_ / "x.xml").string()),
            1);
  // 6 free DOFs hold at most 5 modes: named, nothing written.
  EXPECT_EQ(run("export " + (dir_ / "model.json").string() + " --format reduced --modes 6 -o " +
                (dir_ / "r.json").string()),
            1);
  EXPECT_FALSE(fs::exists(dir_ / "r.json"));
  EXPECT_EQ(run("export " + (dir_ / "model.json").string() + " --format obj -o " +
                (dir_ / "x.xml").string()),
            2);
}

}  // namespace
}  // namespace isospring::io
