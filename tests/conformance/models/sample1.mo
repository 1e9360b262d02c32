// From OpenModelica testsuite/simulation/modelica/events/sample1.mos (loadString content)
// name: sample1
// keywords: event, when, sample
// status: correct
//  case for a sample call
within ;
package eventTests
  model sample1
    Real x;
    Boolean condition;
  algorithm
    condition := sample(0.0, 0.1);
    when condition then
      x := pre(x) + 0.1;
    end when;
  end sample1;
end eventTests;
