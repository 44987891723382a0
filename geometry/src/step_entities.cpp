// STEP entities OpenCascade could not read (step_entities.hpp).
#include "step_entities.hpp"

#include <Interface_Check.hxx>
#include <Interface_ReportEntity.hxx>
#include <StepData_StepModel.hxx>
#include <StepData_UndefinedEntity.hxx>
#include <TCollection_HAsciiString.hxx>

namespace isospring::geometry::detail {

std::string unreadable_step_entities(const Handle(Interface_InterfaceModel) & model) {
  if (model.IsNull()) return "";
  int count = 0;
  std::string listed;
  for (int i = 1; i <= model->NbEntities(); ++i) {
    if (!model->IsUnknownEntity(i) && !model->IsErrorEntity(i)) continue;
    if (++count > 3) continue;
    const Handle(Standard_Transient) entity = model->Value(i);
    // The file's own number (#12), not the model's index; an entity with errors keeps what was
    // read (the misspelled type) as the content of its report.
    const Handle(StepData_StepModel) step = Handle(StepData_StepModel)::DownCast(model);
    const int ident = step.IsNull() ? 0 : step->IdentLabel(entity);
    Handle(Standard_Transient) content = entity;
    const Handle(Interface_ReportEntity) report = model->ReportEntity(i);
    if (!report.IsNull() && !report->Content().IsNull()) content = report->Content();
    const Handle(StepData_UndefinedEntity) undefined =
        Handle(StepData_UndefinedEntity)::DownCast(content);
    std::string why;  // OpenCascade's first complaint, e.g. a reference of the wrong type
    if (!report.IsNull() && !report->Check().IsNull() && report->Check()->NbFails() > 0)
      why = std::string(": ") + report->Check()->CFail(1);
    listed += std::string(listed.empty() ? "" : "; ") +
              (ident > 0 ? "#" + std::to_string(ident) : "entity " + std::to_string(i)) + " " +
              (undefined.IsNull() ? model->TypeName(entity, false) : undefined->StepType()) + why;
  }
  if (count == 0) return "";
  return std::to_string(count) + " entit" + (count == 1 ? "y" : "ies") +
         " OpenCascade cannot read (" + listed + (count > 3 ? "; ..." : "") + ")";
}

}  // namespace isospring::geometry::detail
