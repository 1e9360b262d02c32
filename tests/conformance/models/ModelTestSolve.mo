// From OpenModelica testsuite/simulation/modelica/others/TestSolve.mos (loadString content)
// name: TestSolve
// status: correct
// Checks that the backend knows how to solve certain expressions
model ModelTestSolve
  Real x,y,z;
equation
  ( 1 / x ) * 2 = 1;
  ( y / 1 ) * 2 = 1;
  4 = ( 1 / z ) * 3;
end ModelTestSolve;
