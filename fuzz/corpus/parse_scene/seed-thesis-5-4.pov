CAMERA {
    LOCATION <-18, 7.5, -28>
    LOOK_AT <0.5, 1.07, 0.5>
}

LIGHT_SOURCE { <-10, 12, -30>
    COLOR RGB <1.0, 0.8, 0.8>
}

HEIGHT_FIELD {
    GIF "CANYON.GIF"
    SCALE <1.0, 2.0, 1.0>
    ROTATE <-20, 25, 0>
    TRANSLATE <0, 0, 0>
    COLOR RGB <1.0, 0.8, 0.8>
    IMAGE_MAP
    WATER_LEVEL = 0.01
}
