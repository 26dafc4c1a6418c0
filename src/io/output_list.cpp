// The run's list of outputs (include/fluidbed/outputs.hpp): the defaults of an output's methods, and the calls of
// every output in registration order.
#include "fluidbed/outputs.hpp"

namespace fluidbed {

void Output::Columns(std::vector<MonitorColumn> *) const {}

PetscErrorCode Output::Values(const RunView &, std::vector<PetscReal> *)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::Start(const RunView &)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::Step(const RunView &)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::Finalize(const RunView &)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::Stopped(const RunView &)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::End(const RunView &)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::AddSummary(const RunView &, JsonWriter *)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::CheckpointWrite(const RunView &, PetscViewer)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::CheckpointRead(const RunView &, PetscViewer)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::Restart(const RunView &)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::RemoveStale(const RunView &)
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

PetscErrorCode Output::Destroy()
{
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

namespace {

// call(output) for every output, in order.
template <class Call>
PetscErrorCode Each(const OutputList &list, Call call)
{
  PetscFunctionBeginUser;
  for (const std::unique_ptr<Output> &o : list.outputs) PetscCall(call(*o));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode OutputListAdd(OutputList *list, std::unique_ptr<Output> output)
{
  PetscFunctionBeginUser;
  if (output) list->outputs.push_back(std::move(output));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListCreate(OutputList *list, const RunView &run, OutputCreateFn create, const Output **made)
{
  std::unique_ptr<Output> output;

  PetscFunctionBeginUser;
  PetscCall(create(run, &output));
  if (made) *made = output.get();
  PetscCall(OutputListAdd(list, std::move(output)));
  PetscFunctionReturn(0);
}

void OutputListColumns(const OutputList &list, std::vector<MonitorColumn> *columns)
{
  for (const std::unique_ptr<Output> &o : list.outputs) o->Columns(columns);
}

PetscErrorCode OutputListValues(const OutputList &list, const RunView &run, std::vector<PetscReal> *values)
{
  PetscFunctionBeginUser;
  values->clear();
  for (const std::unique_ptr<Output> &o : list.outputs) {
    std::vector<MonitorColumn> columns;
    const std::size_t          before = values->size();
    o->Columns(&columns);
    PetscCall(o->Values(run, values));
    // a value out of place would shift every later column of the row under another name
    PetscCheck(values->size() - before == columns.size(), run.comm, PETSC_ERR_PLIB, "output %s gave %d values for its %d monitor columns",
               o->Name(), (int)(values->size() - before), (int)columns.size());
  }
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListStart(const OutputList &list, const RunView &run)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.Start(run); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListStep(const OutputList &list, const RunView &run)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.Step(run); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListFinalize(const OutputList &list, const RunView &run)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.Finalize(run); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListStopped(const OutputList &list, const RunView &run)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.Stopped(run); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListEnd(const OutputList &list, const RunView &run)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.End(run); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListAddSummary(const OutputList &list, const RunView &run, JsonWriter *json)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.AddSummary(run, json); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListCheckpointWrite(const OutputList &list, const RunView &run, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.CheckpointWrite(run, viewer); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListCheckpointRead(const OutputList &list, const RunView &run, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.CheckpointRead(run, viewer); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListRestart(const OutputList &list, const RunView &run)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.Restart(run); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListRemoveStale(const OutputList &list, const RunView &run)
{
  PetscFunctionBeginUser;
  PetscCall(Each(list, [&](Output &o) { return o.RemoveStale(run); }));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputListDestroy(OutputList *list)
{
  PetscFunctionBeginUser;
  PetscCall(Each(*list, [](Output &o) { return o.Destroy(); }));
  list->outputs.clear();
  PetscFunctionReturn(0);
}

} // namespace fluidbed
