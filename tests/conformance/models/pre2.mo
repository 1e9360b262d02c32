// From OpenModelica testsuite/simulation/modelica/initialization/pre2.mos (loadString content)
// name: pre2.mos
// keywords: initialization, discrete, pre
// status: correct
//  case for pre variables during initialization
within ;
package initializationTests
  model test_1195b
    parameter Real a = 1.0;
    Real x;           // x = 2
    discrete Real xd; // xd = 2
    Real x1;          // x1 = pre(x) = 2
    Real x2;          // x2 = pre(dx) = 2
  initial equation
    x = 2;
    xd = 2;
  equation
    der(x) = a*x;
    when sample(0,1) then
      xd = a*pre(xd) + pre(x);
    end when;
  equation
    der(x1) = 0;
    der(x2) = 0;
  initial equation
    x1 = pre(x);
    x2 = pre(xd);
  end test_1195b;
end initializationTests;
