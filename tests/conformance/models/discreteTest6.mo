// From OpenModelica testsuite/simulation/modelica/initialization/discreteTest06.mos (loadString content)
// name: discreteTest6
// keywords: initialization, discrete
// status: correct
//  case for an ineffective  initial()-call inside a when-condition
within ;
package initializationTests
  model discreteTest6
    Real x(fixed=true);
    Real y;

  initial equation
    pre(y) = 0;

  equation
    der(x) = y;

    // Disallowed in MLS 3.2r1
    when initial() or time > 0.5 then
      y = pre(y) + 1.0;
    end when;
  end discreteTest6;
end initializationTests;
