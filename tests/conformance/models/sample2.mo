// From OpenModelica testsuite/simulation/modelica/events/sample2.mos (loadString content)
// name: sample2
// keywords: event, when, sample
// status: correct
//  case for a sample call
within ;
package eventTests
  model sample2
    Real x, y;
    Boolean condition1;
    Boolean condition2;
  equation
    condition1 = sample(0.0, 0.1);
    condition2 = sample(0.0, 0.1);
    when condition1 then
      x = pre(x) + 0.1;
    end when;
    when condition2 then
      y = pre(y) + 0.1;
    end when;
  end sample2;
end eventTests;
