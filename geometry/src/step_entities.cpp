// STEP entities OpenCascade could not read (step_entities.hpp).
#include "step_entities.hpp"

#include <Interface_Check.hxx>
#include <Interface_ReportEntity.hxx>
#include <StepData_StepModel.hxx>
#include <StepData_UndefinedEntity.hxx>
#include <StepGeom_GeometricRepresentationItem.hxx>
#include <StepShape_TopologicalRepresentationItem.hxx>
#include <TCollection_HAsciiString.hxx>

#include <cctype>
#include <deque>
#include <fstream>
#include <iterator>
#include <set>
#include <unordered_map>
#include <vector>

namespace isospring::geometry::detail {

namespace {

// The type OpenCascade read for entity `i` (the file's spelling for an undefined entity).
std::string read_type(const Handle(Interface_InterfaceModel) & model, int i) {
  const Handle(Standard_Transient) entity = model->Value(i);
  Handle(Standard_Transient) content = entity;
  const Handle(Interface_ReportEntity) report = model->ReportEntity(i);
  if (!report.IsNull() && !report->Content().IsNull()) content = report->Content();
  const Handle(StepData_UndefinedEntity) undefined =
      Handle(StepData_UndefinedEntity)::DownCast(content);
  if (undefined.IsNull()) return model->TypeName(entity, false);
  // A complex entity, e.g. (LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.)), is a chain.
  std::string type = undefined->StepType();
  for (Handle(StepData_UndefinedEntity) next = undefined->Next(); !next.IsNull();
       next = next->Next())
    type += std::string(" ") + next->StepType();
  return type;
}

// For every entity label of the file's DATA section, the labels of the entities that refer to it.
// Strings ('...', '' inside) and comments are skipped; a record starts with #N= after a ';'.
std::unordered_map<int, std::vector<int>> referrers_in_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::unordered_map<int, std::vector<int>> referrers;
  int current = 0;
  bool record_start = true;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\'') {
      for (++i; i < text.size(); ++i)
        if (text[i] == '\'') {
          if (i + 1 < text.size() && text[i + 1] == '\'') {
            ++i;
            continue;
          }
          break;
        }
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      const size_t end = text.find("*/", i + 2);
      i = end == std::string::npos ? text.size() : end + 1;
    } else if (c == ';') {
      record_start = true;
      current = 0;
    } else if (c == '#') {
      size_t j = i + 1;
      long label = 0;
      while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j])) &&
             label < 1000000000L)
        label = label * 10 + (text[j++] - '0');
      if (j == i + 1) continue;
      size_t k = j;
      while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
      if (record_start && k < text.size() && text[k] == '=') {
        current = static_cast<int>(label);
        record_start = false;
      } else if (current > 0) {
        referrers[static_cast<int>(label)].push_back(current);
      }
      i = j - 1;
    } else if (!std::isspace(static_cast<unsigned char>(c))) {
      record_start = false;
    }
  }
  return referrers;
}

bool is_geometry(const Handle(Standard_Transient) & entity) {
  return !entity.IsNull() &&
         (entity->IsKind(STANDARD_TYPE(StepGeom_GeometricRepresentationItem)) ||
          entity->IsKind(STANDARD_TYPE(StepShape_TopologicalRepresentationItem)));
}

}  // namespace

bool unreadable_entities_outside_geometry(const Handle(Interface_InterfaceModel) & model,
                                          const std::filesystem::path& file) {
  const Handle(StepData_StepModel) step = Handle(StepData_StepModel)::DownCast(model);
  if (step.IsNull()) return false;
  std::unordered_map<int, int> index_of_label;  // file label -> model index
  std::vector<int> unreadable;                  // file labels
  for (int i = 1; i <= model->NbEntities(); ++i) {
    const int label = step->IdentLabel(model->Value(i));
    if (label <= 0) continue;
    index_of_label[label] = i;
    if (!model->IsUnknownEntity(i) && !model->IsErrorEntity(i)) continue;
    // The length unit scales every coordinate: a file whose length unit was not read is wrong
    // however valid its shape looks.
    if (read_type(model, i).find("LENGTH_UNIT") != std::string::npos) return false;
    unreadable.push_back(label);
  }
  if (unreadable.empty()) return false;
  const std::unordered_map<int, std::vector<int>> referrers = referrers_in_text(file);
  std::set<int> seen(unreadable.begin(), unreadable.end());
  std::deque<int> queue(unreadable.begin(), unreadable.end());
  while (!queue.empty()) {
    const int label = queue.front();
    queue.pop_front();
    const auto found = index_of_label.find(label);
    if (found != index_of_label.end() && is_geometry(model->Value(found->second))) return false;
    const auto up = referrers.find(label);
    if (up == referrers.end()) continue;
    for (const int referrer : up->second)
      if (seen.insert(referrer).second) queue.push_back(referrer);
  }
  return true;
}

std::string unreadable_step_entities(const Handle(Interface_InterfaceModel) & model) {
  if (model.IsNull()) return "";
  int count = 0;
  std::string listed;
  for (int i = 1; i <= model->NbEntities(); ++i) {
    if (!model->IsUnknownEntity(i) && !model->IsErrorEntity(i)) continue;
    if (++count > 3) continue;
    const Handle(Standard_Transient) entity = model->Value(i);
    // The file's own number (#12), not the model's index; an entity with errors keeps what was
    // read (the misspelled type) as the content of its report (read_type).
    const Handle(StepData_StepModel) step = Handle(StepData_StepModel)::DownCast(model);
    const int ident = step.IsNull() ? 0 : step->IdentLabel(entity);
    const Handle(Interface_ReportEntity) report = model->ReportEntity(i);
    std::string why;  // OpenCascade's first complaint, e.g. a reference of the wrong type
    if (!report.IsNull() && !report->Check().IsNull() && report->Check()->NbFails() > 0)
      why = std::string(": ") + report->Check()->CFail(1);
    listed += std::string(listed.empty() ? "" : "; ") +
              (ident > 0 ? "#" + std::to_string(ident) : "entity " + std::to_string(i)) + " " +
              read_type(model, i) + why;
  }
  if (count == 0) return "";
  return std::to_string(count) + " entit" + (count == 1 ? "y" : "ies") +
         " OpenCascade cannot read (" + listed + (count > 3 ? "; ..." : "") + ")";
}

}  // namespace isospring::geometry::detail
