// From OpenModelica testsuite/simulation/modelica/others/TestSolve5.mos (loadString content)
// name: TestSolve
// status: correct
// Checks that the backend knows how to solve certain expressions
// test: cos, sin, tan
model ModelTestSolve5
  constant Real s[:] = {-1,1};
  Real[2] x(start=s);
  Real[2] y(start=s);
  Real[2] z(start=s);
  Real err[6];
  Real Err (start = 0, fixed = true);
equation

  for i in 1:2 loop
    cos(x[i]) = 0.5*time;
    sin(y[i]) = 0.5*time;
    tan(z[i]) = 0.5*time;
    err[(i-1)*3 +1] = abs(-cos(x[i]) + 0.5*time);
    err[(i-1)*3 +2] = abs(-sin(y[i]) + 0.5*time);
    err[(i-1)*3 +3] = abs(-tan(z[i]) + 0.5*time);
  end for;

  der(Err) = sum(err);
end ModelTestSolve5;
