// From OpenModelica testsuite/simulation/modelica/indexreduction/DiscreteTupleOutput.mos (loadString content)
// Name:     DiscreteTupleOutput
// keywords: index reduction, smoothOrder, tuple
// status:   correct
//
// Index reduction of a tuple equation with an Integer output.
// The Integer output must not be differentiated.
model DiscreteTupleOutput
  function f
    input Real x;
    output Real y;
    output Integer i = 1;
    output Real z;
  algorithm
    y := x*x;
    z := 3*x;
    for k in 1:3 loop
      if x > k then i := k; end if;
    end for;
    annotation(smoothOrder=100);
  end f;
  Real x, y, xI, z, zI;
  Integer i;
  parameter Real p = 1;
initial equation
  xI = x;
  zI = z;
equation
  (x, i, z) = f(time);
  y = der(x);
  der(xI) = p*y;
  der(zI) = p*der(z);
end DiscreteTupleOutput;
