// From OpenModelica testsuite/simulation/modelica/initialization/testIfAssert.mos (loadString content)
// name: testTicket5294
// keywords: initialization, if equations
// status: correct
model A
  Real x,xd;
  parameter Real lb=5, ub=10;
equation
initial equation
  if x<ub then
    assert(der(x)>49, "Call ub assert\n");
  end if;
  if x<lb then
    assert(der(x)<49, "Call lb assert\n");
  end if;
equation
  der(x) = sin(x*time)+lb*ub;
  xd = der(x);
end A;
