// From OpenModelica testsuite/simulation/modelica/events/noEventEmit.mos (loadString content)
// name: noEventEmit
// keywords: event, result file
// status: correct
model noEventEmit
  discrete Real y(start = 0, fixed = true);
equation
  when sample(0, 0.1) then
    y = time;
  end when;

  annotation(experiment(StartTime = 0, StopTime = 1.0, Interval = 0.02));
end noEventEmit;
