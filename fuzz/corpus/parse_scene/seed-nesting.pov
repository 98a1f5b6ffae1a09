sphere { ((((((((1)))))))), <1,<2,3>.x,3>.y /* nested /* comment */ */ }
