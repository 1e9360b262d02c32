// From OpenModelica testsuite/simulation/modelica/events/bug3358.mos (loadString content)
// name: bug3358
// keywords: events
// status: correct
package bug3358
  model foo3
    Real x(fixed=true, start=0.0);
    Boolean b1, b2;
  equation
    b1 = time > 0.5;
    b2 = time > 0.5;
    when b1 then
      x = pre(x) + 1;
    elsewhen b2 then
      x = pre(x) + 0.1;
    end when;
  end foo3;

  model foo3b
    Real x(fixed=true, start=0.0);
    Boolean b1, b2;
  algorithm
    b2 := time > 0.5;
    b1 := time > 0.5;
    when b1 then
      x := pre(x) + 1;
    elsewhen b2 then
      x := pre(x) + 0.1;
    end when;
  end foo3b;
end bug3358;
