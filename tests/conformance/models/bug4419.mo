// From OpenModelica testsuite/simulation/modelica/events/bug4419.mos (loadString content)
// name: bug4419
// keywords: events
// status: correct
package bug4419
  model test
    Real x(start=0,fixed=true);
    Real y1,y2;
  equation
    der(x)=10;
    y1 = rem(x,2);
    y2 = rem(x+1,2);
  end test;
end bug4419;
