// From OpenModelica testsuite/simulation/modelica/initialization/startValue3.mos (loadString content)
// name: startValue3
// keywords: initialization, start-value, parameter
// status: correct
model startValue3
  parameter Real a(fixed=false);
  parameter Real b(fixed=false);
  Real c(start=a/b, fixed=true);
initial equation
  a=4;
  b=6;
equation
  der(c) = 0;
end startValue3;
