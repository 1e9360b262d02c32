// From OpenModelica testsuite/simulation/modelica/events/EventLoop.mos (loadString content)
// name:     EventIterationLoop
// keywords: EventHandling, EventIterationLoop
// status: correct
//  Simulate model containing EventIterationsLoop
model EventIterationLoop
  Real x(start=1);
  Integer i;
  Boolean b1,b2;
equation
  der(x) = x;
  when {x>1.5,pre(b1),pre(b2)} then
    i = pre(i) + 1;
    b2 = not pre(b2);
  end when;
  when {pre(b1),pre(b2)} then
    b1 = not pre(b1);
  end when;
end EventIterationLoop;
