// From OpenModelica testsuite/simulation/modelica/initialization/startValue1.mos (loadString content)
// name: startValue1
// keywords: initialization, start-value, states
// status: correct
model startValue1
  parameter Real p1(fixed=false);
  parameter Real p2 = 2.0;
  Real x(start=p1, fixed=true);
  Real y(start=p2, fixed=true);
initial equation
  p1 = 1.0;
equation
  der(x)=0;
  der(y)=0;
end startValue1;
