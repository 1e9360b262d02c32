// From OpenModelica testsuite/simulation/modelica/events/EventTests2.mos (loadString content)
// name:     EventTest2
// keywords: EventHandling, Realations
// status: correct
model testEvents2
  Boolean a = time < -0.2;
  Boolean b = time <= -0.1;
  Boolean c = time > 0.1;
  Boolean d = time >= 0.2;
  annotation (experiment(StartTime=-1, StopTime=1));
end testEvents2;
