// End-to-end table of bad inputs across the commands: corrupted STEP files, numbers
// that overflow a double, outputs that are inputs, unwritable output folders, loads and
// materials whose results overflow, and sizes beyond the machine. Each must end with exit status
// 1, 2 or 3 (never 4, never a signal) within seconds, with a message naming the file or the
// field, and leave every input byte-identical and no output behind.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <string>

#include "run_program.hpp"

namespace {
namespace fs = std::filesystem;
using isospring::testing::example;
using isospring::testing::file_contents;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;

struct BadInput {
  const char* name;
  std::string arguments;  // "{d}" stands for the folder holding the inputs
  std::string expected;   // part of the message: the file or the field ({d} replaced too)
  std::set<int> codes = {1};
};

// ctest lists the case by its name, not by the bytes of the struct.
void PrintTo(const BadInput& bad, std::ostream* out) {
  *out << bad.name;
}

std::string replaced(std::string text, const std::string& dir) {
  for (size_t at = text.find("{d}"); at != std::string::npos; at = text.find("{d}", at))
    text.replace(at, 3, dir);
  return text;
}

// A small clamped box (2 x 1 x 1 quadratic elements: solves in milliseconds); each field can be
// replaced by text, e.g. an overflowing number.
std::string box_case(
    const std::string& size = "0.1", const std::string& elements = "[2, 1, 1]",
    const std::string& modulus = "50000", const std::string& density = "1100",
    const std::string& load = R"("tractions": [{"side": "u1", "value": [0, 0, -100]}])") {
  return R"({"name": "box", "geometry": {"type": "box", "size": [)" + size +
         R"(, 0.02, 0.02]},
 "discretization": {"degree": [2, 2, 2], "elements": )" +
         elements + R"(},
 "material": {"E": )" +
         modulus + R"(, "nu": 0.3, "density": )" + density + R"(},
 "boundary": [{"side": "u0", "fix": ["x", "y", "z"]}],
 "load_cases": [{"id": "L1", )" +
         load + "}]}\n";
}

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Writes a file under `dir`, creating its folders.
struct InputWriter {
  fs::path dir;
  void operator()(const std::string& name, const std::string& text) const {
    fs::create_directories((dir / name).parent_path());
    std::ofstream(dir / name, std::ios::binary) << text;
  }
};

// Valid inputs the table's commands start from, and files where folders are expected.
void write_valid_inputs(const InputWriter& write) {
  const fs::path& dir = write.dir;
  const std::string patches = file_contents(example("patches/quarter_annulus.json"));
  write("p.json", patches);
  write("o.json.report.json", patches);
  fs::create_symlink(dir / "p.json", dir / "link.json");
  write("model.json", R"({"format": "isospring-spring-model", "version": 1, "dimension": 3,
    "particles": [{"x": [0, 0, 0], "mass": 1, "fixed": true},
                  {"x": [0, 0, -0.1], "mass": 1, "fixed": false}],
    "springs": [{"i": 0, "j": 1, "k": 100, "c": 1, "L0": 0.1}]})");
  write("sim/report.json", file_contents(dir / "model.json"));
  write("case.json", box_case());
  write("rep/report.json", box_case());
  write("deck.inp.report.json", box_case());
  write("block.step", file_contents(example("cad/block.step")));
  write("afile", "a file where a folder is expected\n");
}

// CAD files OpenCascade cannot read.
void write_corrupted_parts(const InputWriter& write) {
  const std::string step = file_contents(example("cad/block.step"));
  // Corrupted parts: a misspelled entity (OpenCascade used to crash on it), one in a B-spline
  // free part of the file, and a file cut in half.
  write("misspelled.step", replace_once(step, "CARTESIAN_POINT(", "CARTESIAN_POINTX("));
  write("misspelled2.step", replace_once(step, "DIRECTION(", "DIRECTIOM("));
  write("truncated.step", step.substr(0, step.size() / 2));
  // Byte-mutated IGES exports of the block (tests/apps/data): the first made OpenCascade's reader
  // segfault, the second made it throw Standard_Failure (which ended the program with abort).
  const std::string data = std::string(ISOSPRING_SOURCE_DIR) + "/tests/apps/data/";
  write("crashes.igs", file_contents(data + "block_crashes_opencascade.igs"));
  write("void_bounds.igs", file_contents(data + "block_void_bounds.igs"));
  write("cad_case.json", replace_once(file_contents(example("demo/demo.json")), "../cad/block.step",
                                      "misspelled.step"));
}

// Numbers a double cannot hold, finite inputs whose results are not, and sizes beyond the
// machine.
void write_unrepresentable_numbers(const InputWriter& write) {
  const std::string patches = file_contents(example("patches/quarter_annulus.json"));
  // Numbers a double cannot hold.
  write("e_overflow.json", box_case("0.1", "[2, 1, 1]", "1e999"));
  write("size_overflow.json", box_case("1e999"));
  write("density_overflow.json", box_case("0.1", "[2, 1, 1]", "50000", "1e999"));
  write("traction_overflow.json",
        box_case("0.1", "[2, 1, 1]", "50000", "1100",
                 R"("tractions": [{"side": "u1", "value": [0, 0, -1e999]}])"));
  write("point_load_overflow.json",
        box_case("0.1", "[2, 1, 1]", "50000", "1100",
                 R"("point_loads": [{"control_point": [-1, -1, -1], "force": [0, 1e999, 0]}])"));
  write("patch_overflow.json", replace_once(patches, "[2, 2, 0]", "[2, 2e999, 0]"));
  write("model_overflow.json",
        replace_once(file_contents(write.dir / "model.json"), "\"k\": 100", "\"k\": 1e999"));
  // Finite inputs whose results are not.
  write("traction_huge.json",
        box_case("0.1", "[2, 1, 1]", "50000", "1100",
                 R"("tractions": [{"side": "u1", "value": [0, 0, -1e308]}])"));
  write("weight_huge.json",
        box_case("0.1", "[2, 1, 1]", "50000", "1e308", R"("gravity": [0, 0, -9.81])"));
  write("modulus_tiny.json", box_case("0.1", "[2, 1, 1]", "1e-300"));
  write("zero_load.json", box_case("0.1", "[2, 1, 1]", "50000", "1100",
                                   R"("tractions": [{"side": "u1", "value": [0, 0, 0]}])"));
  write("eval_huge.json", R"({"patches": [{"degrees": [1], "knots": [[0, 0, 1, 1]],
    "control_points": [[-1.7e308, 0, 0], [1.7e308, 0, 0]]}]})");
  // Sizes beyond the machine.
  write("huge_mesh.json", box_case("0.1", "[100000, 1000, 1000]"));
  write("big_mesh.json", box_case("0.1", "[20, 4, 4]"));
}

// Malformed and inconsistent case files (bad/): the box case with one field broken.
void write_malformed_cases(const InputWriter& write) {
  write("bad/syntax.json", R"BAD({"name": "box", "geometry": {"type": "box",, })BAD");
  write("bad/empty.json", R"BAD()BAD");
  write("bad/array.json", R"BAD([1,2,3])BAD");
  const std::string box = box_case();
  const auto broken = [&](const std::string& from, const std::string& to) {
    if (box.find(from) == std::string::npos)
      throw std::logic_error("the box case holds no " + from + " to break");
    return replace_once(box, from, to);
  };
  write("bad/nu_half.json", broken(R"("nu": 0.3)", R"("nu": 0.5)"));
  write("bad/nu_neg.json", broken(R"("nu": 0.3)", R"("nu": -1.5)"));
  write("bad/e_neg.json", box_case("0.1", "[2, 1, 1]", "-5"));
  write("bad/e_string.json", box_case("0.1", "[2, 1, 1]", R"("fifty")"));
  write("bad/no_material.json",
        broken(R"( "material": {"E": 50000, "nu": 0.3, "density": 1100},)", ""));
  write("bad/no_loads.json",
        broken(R"([{"id": "L1", "tractions": [{"side": "u1", "value": [0, 0, -100]}]}])", "[]"));
  write("bad/no_boundary.json", broken(R"([{"side": "u0", "fix": ["x", "y", "z"]}])", "[]"));
  write("bad/bad_side.json", broken(R"("side": "u0")", R"("side": "w7")"));
  write("bad/bad_fix.json", broken(R"("fix": ["x", "y", "z"])", R"("fix": ["q"])"));
  write("bad/bad_geom.json", broken(R"("type": "box")", R"("type": "dodecahedron")"));
  write("bad/neg_size.json", box_case("-0.1"));
  write("bad/zero_elems.json", box_case("0.1", "[0, 1, 1]"));
  write("bad/deg_zero.json", broken(R"("degree": [2, 2, 2])", R"("degree": [0, 2, 2])"));
  write("bad/trac_dim.json", box_case("0.1", "[2, 1, 1]", "50000", "1100",
                                      R"("tractions": [{"side": "u1", "value": [0, -100]}])"));
  const std::string traction = R"("tractions": [{"side": "u1", "value": [0, 0, -100]}])";
  write("bad/dup_ids.json",
        box_case("0.1", "[2, 1, 1]", "50000", "1100", traction + R"(}, {"id": "L1", )" + traction));
  const std::string end_of_case = "}]}\n";
  write("bad/unknown_field.json",
        broken(end_of_case, R"(}], "materials": {}})" + std::string("\n")));
}

// Malformed patches, spring models and marker files (bad/).
void write_malformed_patches_and_models(const InputWriter& write) {
  write(
      "bad/patch_wrong_knots.json",
      R"BAD({"patches": [{"degrees": [1], "knots": [[0, 0.5, 0, 1]], "control_points": [[0,0,0],[1,0,0]]}]})BAD");
  write(
      "bad/patch_neg_weight.json",
      R"BAD({"patches": [{"degrees": [1], "knots": [[0, 0, 1, 1]], "control_points": [[0,0,0],[1,0,0]], "weights": [1, -1]}]})BAD");
  write(
      "bad/patch_zero_weight.json",
      R"BAD({"patches": [{"degrees": [1], "knots": [[0, 0, 1, 1]], "control_points": [[0,0,0],[1,0,0]], "weights": [1, 0]}]})BAD");
  write(
      "bad/patch_count.json",
      R"BAD({"patches": [{"degrees": [1], "knots": [[0, 0, 1, 1]], "control_points": [[0,0,0],[1,0,0],[2,0,0]]}]})BAD");
  write(
      "bad/patch_nan.json",
      R"BAD({"patches": [{"degrees": [1], "knots": [[0, 0, 1, 1]], "control_points": [[0,0,0],[NaN,0,0]]}]})BAD");
  write("bad/patch_empty.json", R"BAD({"patches": []})BAD");
  write(
      "bad/model_bad_index.json",
      R"BAD({"format": "isospring-spring-model", "version": 1, "dimension": 3, "particles": [{"x": [0,0,0], "mass": 1, "fixed": true}], "springs": [{"i": 0, "j": 5, "k": 100, "c": 1, "L0": 0.1}]})BAD");
  write(
      "bad/model_neg_mass.json",
      R"BAD({"format": "isospring-spring-model", "version": 1, "dimension": 3, "particles": [{"x": [0,0,0], "mass": 1, "fixed": true},{"x": [0,0,-0.1], "mass": -1, "fixed": false}], "springs": [{"i": 0, "j": 1, "k": 100, "c": 1, "L0": 0.1}]})BAD");
  write("bad/model_format.json", R"BAD({"format": "something-else", "version": 1})BAD");
  write(
      "bad/model_version.json",
      R"BAD({"format": "isospring-spring-model", "version": 99, "dimension": 3, "particles": [], "springs": []})BAD");
  write("bad/badrow.csv", R"BAD(load_case,x,y,ux,uy
L1,0.01,0.003,1e-6
)BAD");
  write("bad/far.csv", R"BAD(load_case,x,y,ux,uy
L1,5.0,5.0,1e-6,1e-6
)BAD");
}

// Measured-data cases (identify): the shipped example with one field broken (bad/).
void write_bad_identify_cases(const InputWriter& write) {
  const std::string markers = std::string(ISOSPRING_SOURCE_DIR) + "/examples/identify/markers.csv";
  nlohmann::json id_case =
      nlohmann::json::parse(file_contents(example("identify/plate_hidden_gravity.json")));
  id_case["measurements"]["file"] = markers;
  const auto id_variant = [&](const std::string& name, const std::string& key,
                              const nlohmann::json& value) {
    nlohmann::json c = id_case;
    c["measurements"][key] = value;
    write("bad/" + name, c.dump(1));
  };
  id_variant("id_missing_csv.json", "file", nlohmann::json::parse(R"BAD("missing.csv")BAD"));
  id_variant("id_bad_effect.json", "effects", nlohmann::json::parse(R"BAD(["telekinesis"])BAD"));
  id_variant("id_bad_units.json", "units", nlohmann::json::parse(R"BAD("furlong")BAD"));
  id_variant("id_bad_sig.json", "significance", nlohmann::json::parse(R"BAD(2)BAD"));
  id_variant("id_bad_weights.json", "component_weights", nlohmann::json::parse(R"BAD([1, -1])BAD"));
  id_variant("id_bad_weights2.json", "component_weights",
             nlohmann::json::parse(R"BAD("median")BAD"));
  id_variant("id_bad_column.json", "columns",
             nlohmann::json::parse(R"BAD({"ux": "displacement_x"})BAD"));
  id_variant("id_neg_noise.json", "noise_sigma", nlohmann::json::parse(R"BAD(-1)BAD"));
  id_variant("id_bad_lc.json", "load_case", nlohmann::json::parse(R"BAD("L7")BAD"));
  id_variant("id_short_row.json", "file", nlohmann::json::parse(R"BAD("badrow.csv")BAD"));
  id_variant("id_far.json", "file", nlohmann::json::parse(R"BAD("far.csv")BAD"));
  id_variant("id_budget.json", "max_dofs", nlohmann::json::parse(R"BAD(10)BAD"));
  {
    nlohmann::json c = id_case;
    c.erase("measurements");
    write("bad/id_no_meas.json", c.dump(1));
  }
}

// Every input of the table, written into `dir`.
void write_inputs(const fs::path& dir) {
  const InputWriter write{dir};
  write_valid_inputs(write);
  write_corrupted_parts(write);
  write_unrepresentable_numbers(write);
  write_malformed_cases(write);
  write_malformed_patches_and_models(write);
  write_bad_identify_cases(write);
}

// Every file and folder under `dir` with its contents (symlinks as their target).
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = fs::relative(entry.path(), dir).string();
    if (entry.is_symlink())
      files[name] = "-> " + fs::read_symlink(entry.path()).string();
    else if (entry.is_directory())
      files[name] = "<folder>";
    else
      files[name] = file_contents(entry.path().string());
  }
  return files;
}

class BadInputs : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputs, FailCleanlyNamingTheProblem) {
  const BadInput& bad = GetParam();
  TemporaryFolder folder;
  const std::string dir = folder.path().string();
  write_inputs(folder.path());
  const auto before = snapshot(folder.path());
  const auto start = std::chrono::steady_clock::now();
  const auto run = run_isospring(replaced(bad.arguments, dir));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(bad.codes.count(run.exit_code))
      << "exit " << run.exit_code << " (-1: killed by a signal)\n"
      << run.output;
  EXPECT_NE(run.output.find(replaced(bad.expected, dir)), std::string::npos)
      << "expected '" << replaced(bad.expected, dir) << "' in\n"
      << run.output;
  EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
  EXPECT_LT(seconds, 5.0);
  const auto after = snapshot(folder.path());
  EXPECT_EQ(after.size(), before.size()) << "files were added or removed\n" << run.output;
  for (const auto& [name, contents] : before) {
    const auto found = after.find(name);
    ASSERT_NE(found, after.end()) << name << " disappeared";
    EXPECT_TRUE(found->second == contents) << name << " was modified";
  }
}

const std::string kOverwrite = "would overwrite the input";
const std::string kOverflow = "does not fit in a double";

INSTANTIATE_TEST_SUITE_P(
    AcrossCommands, BadInputs,
    ::testing::Values(
        // 1. Outputs that are inputs.
        BadInput{"RefineOntoItsInput", "refine {d}/p.json -o {d}/p.json", kOverwrite},
        BadInput{"RefineThroughASymlink", "refine {d}/p.json -o {d}/link.json", "{d}/link.json"},
        BadInput{"RefineReportOntoTheInput", "refine {d}/o.json.report.json -o {d}/o.json",
                 "{d}/o.json.report.json"},
        BadInput{"ExportOntoItsInput", "export {d}/model.json -o {d}/model.json", kOverwrite},
        BadInput{"ImportOntoItsInput", "import {d}/block.step -o {d}/block.step", kOverwrite},
        BadInput{"AnalyzeReportOntoTheCase", "analyze {d}/rep/report.json -o {d}/rep",
                 "{d}/rep/report.json"},
        BadInput{"ExportStepOntoItsInput", "export-step {d}/p.json -o {d}/p.json", kOverwrite},
        BadInput{"CalculixReportOntoTheCase",
                 "export-calculix {d}/deck.inp.report.json -o {d}/deck.inp",
                 "{d}/deck.inp.report.json"},
        BadInput{"SimulateReportOntoTheModel", "simulate {d}/sim/report.json -o {d}/sim --dt 0.01",
                 "{d}/sim/report.json"},
        // 2. Numbers that overflow a double.
        BadInput{"AnalyzeModulus1e999", "analyze {d}/e_overflow.json -o {d}/out",
                 "e_overflow.json: line 3, column 20: material.E = 1e999"},
        BadInput{"AnalyzeSize1e999", "analyze {d}/size_overflow.json -o {d}/out",
                 "geometry.size[0] = 1e999"},
        BadInput{"AnalyzeDensity1e999", "analyze {d}/density_overflow.json -o {d}/out",
                 "material.density = 1e999"},
        BadInput{"AnalyzeTraction1e999", "analyze {d}/traction_overflow.json -o {d}/out",
                 "load_cases[0].tractions[0].value[2] = -1e999"},
        BadInput{"AnalyzePointLoad1e999", "analyze {d}/point_load_overflow.json -o {d}/out",
                 "load_cases[0].point_loads[0].force[1] = 1e999"},
        BadInput{"CalibrateModulus1e999", "calibrate {d}/e_overflow.json -o {d}/out",
                 "material.E = 1e999"},
        BadInput{"InfoModulus1e999", "info {d}/e_overflow.json", "material.E = 1e999"},
        BadInput{"RefinePatch1e999", "refine {d}/patch_overflow.json -o {d}/r.json",
                 "patches[0].control_points[4][1] = 2e999"},
        BadInput{"EvalPatch1e999", "eval {d}/patch_overflow.json --at 0.5,0.5",
                 "patch_overflow.json: line"},
        BadInput{"ExportModel1e999", "export {d}/model_overflow.json -o {d}/m.xml",
                 "springs[0].k = 1e999"},
        BadInput{"SimulateModel1e999", "simulate {d}/model_overflow.json -o {d}/out --dt 0.01",
                 "springs[0].k = 1e999"},
        // 3. Output folders that cannot be written: exit 1 for every command, before computing.
        BadInput{"AnalyzeIntoAFile", "analyze {d}/case.json -o {d}/afile/out", "is not a folder"},
        BadInput{"StudyIntoAFile", "study {d}/case.json -o {d}/afile/out", "{d}/afile/out"},
        BadInput{"CalibrateIntoAFile",
                 "calibrate " + example("calibrate_square.json") + " -o {d}/afile/out",
                 "{d}/afile/out"},
        BadInput{"IdentifyIntoAFile",
                 "identify " + example("identify/plate_hidden_gravity.json") + " -o {d}/afile/out",
                 "{d}/afile/out"},
        BadInput{"ThesisIntoAFile", "thesis -o {d}/afile/out", "{d}/afile/out"},
        BadInput{"ImportIntoAFile", "import {d}/block.step -o {d}/afile/b.json", "{d}/afile"},
        BadInput{"ImportDisplayIntoAFile",
                 "import {d}/block.step -o {d}/b.json --display {d}/afile/b.vtp", "{d}/afile"},
        BadInput{"ExportStepIntoSys", "export-step {d}/p.json -o /sys/isospring.step",
                 "Permission denied"},
        BadInput{"RefineIntoSys", "refine {d}/p.json -o /sys/isospring.json", "/sys"},
        BadInput{"SimulateIntoSys", "simulate {d}/model.json -o /sys/isospring --dt 0.01",
                 "/sys/isospring"},
        BadInput{"DemoIntoSys", "demo -o /sys/isospring", "/sys/isospring"},
        // 4. Results that overflow (exit 3, naming the load case), and an all-zero load.
        BadInput{"AnalyzeTraction1e308",
                 "analyze {d}/traction_huge.json -o {d}/out",
                 "load case 'L1'",
                 {3}},
        BadInput{"AnalyzeDensity1e308",
                 "analyze {d}/weight_huge.json -o {d}/out",
                 "load case 'L1': the load vector overflowed",
                 {3}},
        BadInput{"AnalyzeModulus1em300",
                 "analyze {d}/modulus_tiny.json -o {d}/out",
                 "load case 'L1'",
                 {3}},
        BadInput{"EvalOverflowingPoint",
                 "eval {d}/eval_huge.json --at 0.5 --derivs",
                 "eval_huge.json: patch 0 at 0.5",
                 {3}},
        BadInput{"AnalyzeZeroLoad", "analyze {d}/zero_load.json -o {d}/out",
                 "zero_load.json: load_cases[0] (id 'L1') has no load"},
        // 5. Corrupted STEP files.
        BadInput{"InfoMisspelledEntity", "info {d}/misspelled.step",
                 "{d}/misspelled.step: 1 entity OpenCascade cannot read"},
        BadInput{"ImportMisspelledEntity", "import {d}/misspelled.step -o {d}/m.json",
                 "{d}/misspelled.step"},
        BadInput{"ImportMisspelledDirection", "import {d}/misspelled2.step -o {d}/m.json",
                 "{d}/misspelled2.step"},
        BadInput{"ImportTruncated", "import {d}/truncated.step -o {d}/m.json",
                 "{d}/truncated.step"},
        BadInput{"ImportIgesThatCrashedOpenCascade", "import {d}/crashes.igs -o {d}/m.json",
                 "{d}/crashes.igs: OpenCascade crashed"},
        BadInput{"InfoIgesThatCrashedOpenCascade", "info {d}/crashes.igs", "{d}/crashes.igs"},
        BadInput{"ImportIgesThatThrew", "import {d}/void_bounds.igs -o {d}/m.json",
                 "{d}/void_bounds.igs: OpenCascade failed"},
        BadInput{"AnalyzeCadCaseMisspelled", "analyze {d}/cad_case.json -o {d}/out",
                 "misspelled.step"},
        // 6. Sizes beyond the machine.
        BadInput{"AnalyzeHugeMesh", "analyze {d}/huge_mesh.json -o {d}/out",
                 "100000 x 1000 x 1000 elements"},
        BadInput{"AnalyzeBeyondMaxMemory", "analyze {d}/big_mesh.json -o {d}/out --max-memory 0.01",
                 "(--max-memory 0.01 GB)"},
        BadInput{"StudyFinestLevelTooLarge", "study {d}/big_mesh.json -o {d}/out --levels 8",
                 "2560 x 512 x 512 elements"},
        BadInput{"RefineHugeH", "refine {d}/p.json -o {d}/r.json --h 1000000", "control points"},
        // 7. Malformed and inconsistent files and options of every command.
        BadInput{"InfoSyntaxError", "info {d}/bad/syntax.json",
                 "syntax.json: line 1, column 38: not valid JSON"},
        BadInput{"InfoEmptyFile", "info {d}/bad/empty.json",
                 "empty.json: line 1, column 1: not valid JSON"},
        BadInput{"InfoJsonArray", "info {d}/bad/array.json", "array.json: neither a patch file"},
        BadInput{"AnalyzeIncompressible", "analyze {d}/bad/nu_half.json -o {d}/out",
                 "material.nu must be in (-1, 0.5)"},
        BadInput{"AnalyzePoissonBelowMinusOne", "analyze {d}/bad/nu_neg.json -o {d}/out",
                 "got -1.5"},
        BadInput{"AnalyzeNegativeModulus", "analyze {d}/bad/e_neg.json -o {d}/out",
                 "material.E must be > 0"},
        BadInput{"AnalyzeModulusAsText", "analyze {d}/bad/e_string.json -o {d}/out",
                 "material.E must be a number, got string"},
        BadInput{"AnalyzeNoMaterial", "analyze {d}/bad/no_material.json -o {d}/out",
                 "material is missing"},
        BadInput{"AnalyzeNoLoadCases", "analyze {d}/bad/no_loads.json -o {d}/out",
                 "load_cases must not be empty"},
        BadInput{"AnalyzeNoSupports", "analyze {d}/bad/no_boundary.json -o {d}/out",
                 "boundary must not be empty"},
        BadInput{"AnalyzeUnknownSide", "analyze {d}/bad/bad_side.json -o {d}/out",
                 "unknown side 'w7'; did you mean 'w0'?"},
        BadInput{"AnalyzeUnknownComponent", "analyze {d}/bad/bad_fix.json -o {d}/out",
                 "boundary[0].fix[0]: 'q' is not a displacement component"},
        BadInput{"AnalyzeUnknownGeometry", "analyze {d}/bad/bad_geom.json -o {d}/out",
                 "geometry.type 'dodecahedron' is unknown"},
        BadInput{"AnalyzeNegativeSize", "analyze {d}/bad/neg_size.json -o {d}/out",
                 "size[0] must be a positive number"},
        BadInput{"AnalyzeZeroElements", "analyze {d}/bad/zero_elems.json -o {d}/out",
                 "discretization.elements must be >= 1"},
        BadInput{"AnalyzeDegreeZero", "analyze {d}/bad/deg_zero.json -o {d}/out",
                 "discretization.degree must be >= 1"},
        BadInput{"AnalyzeTractionOfWrongSize", "analyze {d}/bad/trac_dim.json -o {d}/out",
                 "tractions[0].value must be an array of 3 numbers"},
        BadInput{"AnalyzeDuplicateLoadCase", "analyze {d}/bad/dup_ids.json -o {d}/out",
                 "load case id 'L1' is used twice"},
        BadInput{"AnalyzeMisspelledField", "analyze {d}/bad/unknown_field.json -o {d}/out",
                 "materials: unknown field; did you mean 'material'?"},
        BadInput{"StudySyntaxError", "study {d}/bad/syntax.json -o {d}/out",
                 "syntax.json: line 1, column 38"},
        BadInput{"CalibrateNoSupports", "calibrate {d}/bad/no_boundary.json -o {d}/out",
                 "boundary must not be empty"},
        BadInput{"CalculixBadPoisson", "export-calculix {d}/bad/nu_neg.json -o {d}/d.inp",
                 "material.nu must be in (-1, 0.5)"},
        BadInput{"AnalyzeAPatchFile", "analyze {d}/p.json -o {d}/out", "patches: unknown field"},
        BadInput{"InfoDecreasingKnots", "info {d}/bad/patch_wrong_knots.json",
                 "knots must not decrease"},
        BadInput{"InfoNegativeWeight", "info {d}/bad/patch_neg_weight.json",
                 "weights[1] = -1.000000 must be > 0"},
        BadInput{"InfoZeroWeight", "info {d}/bad/patch_zero_weight.json",
                 "weights[1] = 0.000000 must be > 0"},
        BadInput{"InfoPointCountMismatch", "info {d}/bad/patch_count.json",
                 "control_points has 3 points, but the knots give 2"},
        BadInput{"InfoNaNLiteral", "info {d}/bad/patch_nan.json",
                 "patch_nan.json: line 1, column 80: not valid JSON"},
        BadInput{"InfoNoPatches", "info {d}/bad/patch_empty.json",
                 "patches must be a non-empty array"},
        BadInput{"RefineNaNLiteral", "refine {d}/bad/patch_nan.json -o {d}/r.json",
                 "patch_nan.json: line 1"},
        BadInput{"ExportStepNaNLiteral", "export-step {d}/bad/patch_nan.json -o {d}/x.step",
                 "patch_nan.json: line 1"},
        BadInput{"EvalOutsideTheParameterRange", "eval {d}/p.json --at 7,0.5",
                 "parameter 7.000000 lies outside [0.000000, 1.000000]"},
        BadInput{"EvalNotANumber", "eval {d}/p.json --at abc", "'abc' in 'abc' is not a number"},
        BadInput{"RefineNegativeH",
                 "refine {d}/p.json -o {d}/r.json --h -3",
                 "--h: must be a positive finite number, got -3",
                 {2}},
        BadInput{"RefineHNotANumber",
                 "refine {d}/p.json -o {d}/r.json --h abc",
                 "--h: 'abc' is not a number",
                 {2}},
        BadInput{"AnalyzeNegativeMaxMemory",
                 "analyze {d}/case.json -o {d}/out --max-memory -1",
                 "--max-memory: must be a positive finite number",
                 {2}},
        BadInput{"InfoMissingFile", "info {d}/nonexistent.json", "File does not exist", {2}},
        BadInput{"InfoAFolder", "info {d}/rep", "File is actually a directory", {2}},
        BadInput{"ExportSpringOutOfRange", "export {d}/bad/model_bad_index.json -o {d}/m.xml",
                 "springs[0].j: particle index 5 out of range"},
        BadInput{"SimulateNegativeMass",
                 "simulate {d}/bad/model_neg_mass.json -o {d}/out --dt 0.01",
                 "particles[1].mass: must be finite and > 0"},
        BadInput{"SimulateZeroTimeStep", "simulate {d}/model.json -o {d}/out --dt 0",
                 "--dt: must be a positive time step"},
        BadInput{"ExportNotAModel", "export {d}/bad/model_format.json -o {d}/m.xml",
                 "format: must be \"isospring-spring-model\""},
        BadInput{"ExportFutureVersion", "export {d}/bad/model_version.json -o {d}/m.xml",
                 "version: unsupported version"},
        BadInput{"ExportAPatchFile", "export {d}/p.json -o {d}/m.xml", "patches: unknown field"},
        BadInput{"SimulateACsvFile", "simulate {d}/bad/badrow.csv -o {d}/out --dt 0.01",
                 "badrow.csv: line 1, column 1: not valid JSON"},
        BadInput{"IdentifyMissingCsv", "identify {d}/bad/id_missing_csv.json -o {d}/out",
                 "measurements.file: 'missing.csv' does not exist"},
        BadInput{"IdentifyUnknownEffect", "identify {d}/bad/id_bad_effect.json -o {d}/out",
                 "\"telekinesis\" is not an effect"},
        BadInput{"IdentifyUnknownUnits", "identify {d}/bad/id_bad_units.json -o {d}/out",
                 "measurements.units: \"furlong\""},
        BadInput{"IdentifySignificanceAboveHalf", "identify {d}/bad/id_bad_sig.json -o {d}/out",
                 "measurements.significance must be in (0, 0.5), got 2"},
        BadInput{"IdentifyNegativeComponentWeight",
                 "identify {d}/bad/id_bad_weights.json -o {d}/out",
                 "component_weights[1] must be > 0"},
        BadInput{"IdentifyUnknownWeighting", "identify {d}/bad/id_bad_weights2.json -o {d}/out",
                 "must be \"mean_abs\" or a list of 2"},
        BadInput{"IdentifyNoMeasurements", "identify {d}/bad/id_no_meas.json -o {d}/out",
                 "no \"measurements\" object"},
        BadInput{"IdentifyMissingColumn", "identify {d}/bad/id_bad_column.json -o {d}/out",
                 "no column \"displacement_x\" in the header"},
        BadInput{"IdentifyNegativeNoise", "identify {d}/bad/id_neg_noise.json -o {d}/out",
                 "noise_sigma must be in (0, 1e+300), got -1"},
        BadInput{"IdentifyUnknownLoadCase", "identify {d}/bad/id_bad_lc.json -o {d}/out",
                 "measurements.load_case: \"L7\" is not a load case"},
        BadInput{"IdentifyShortRow", "identify {d}/bad/id_short_row.json -o {d}/out",
                 "badrow.csv: row 2, column \"uy\": missing value"},
        BadInput{"IdentifyMarkerFarOffTheModel", "identify {d}/bad/id_far.json -o {d}/out",
                 "far.csv: 1 marker(s) lie farther than"},
        BadInput{"IdentifyBudgetAllowsNoRefinement", "identify {d}/bad/id_budget.json -o {d}/out",
                 "allows no refinement of the case"}),
    [](const ::testing::TestParamInfo<BadInput>& info) { return std::string(info.param.name); });

}  // namespace
