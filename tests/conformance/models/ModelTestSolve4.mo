// From OpenModelica testsuite/simulation/modelica/others/TestSolve4.mos (loadString content)
// name: TestSolve
// status: correct
// Checks that the backend knows how to solve certain expressions
// test: cosh, sinh, tanh
model ModelTestSolve4
  constant Real s[2] = {-1,1};
  Real[2] x(start=s);
  Real[2] y(start=s);
  Real[2] z(start=s);
  Real err[6];
  Real Err (start = 0, fixed = true);
equation
  for i in 1:2 loop
    cosh(x[i]) = 1.1 + 0.5*time;
    sinh(y[i]) = 1.1 + 0.5*time;
    tanh(z[i]) = 0.5*time;
    err[(i-1)*3 +1] = abs(-cosh(x[i]) + 1.1 + 0.5*time);
    err[(i-1)*3 +2] = abs(-sinh(y[i]) + 1.1 + 0.5*time);
    err[(i-1)*3 +3] = abs(-tanh(z[i]) +  0.5*time);
  end for;

  der(Err) = sum(err);
end ModelTestSolve4;
